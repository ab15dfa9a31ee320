/* deflate_join: raw deflate streams (RFC 1951) made by a whole-buffer
 * compressor, joined into one stream, the way pigz joins its pieces.
 *
 * A whole-buffer compressor (libdeflate) ends every stream with a final
 * block and cannot flush, so two of its streams cannot simply follow each
 * other. deflate_walk reads a stream's blocks without writing out what
 * they decode to (Huffman codes and extra bits only) and finds where the
 * final block's header is and where the stream ends; deflate_unfinal then
 * clears that header's BFINAL bit and appends an empty stored block, which
 * brings the stream to a byte boundary (a sync flush, as zlib's deflate
 * writes one). The next stream then starts on that boundary. Streams that
 * were compressed apart refer to nothing before their own start, so the
 * joined stream decodes to the pieces' data one after the other.
 *
 * The zlib wrapper's checksum of the whole is deflate_adler32_combine of the
 * pieces' checksums. */
#ifndef GLINT_IO_DEFLATE_JOIN_H
#define GLINT_IO_DEFLATE_JOIN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Bytes deflate_unfinal may add to a stream. */
#define DEFLATE_UNFINAL_EXTRA 5

typedef struct deflate_ends {
    size_t final_header; /* bit offset of the final block's header (its BFINAL bit) */
    size_t end;          /* bit offset just past the final block's end-of-block code */
} deflate_ends;

/* Walks the raw deflate stream z[0..n): true when it is a well-formed
 * stream that decodes to exactly expect bytes, refers to nothing before
 * its own start, and whose final block ends in its last byte; *ends then
 * says where that block is. False for anything else (the caller then
 * keeps the stream whole). */
bool deflate_walk(const uint8_t *z, size_t n, size_t expect, deflate_ends *ends);

/* Makes the walked stream z[0..*n) non-final and byte-aligned: clears the
 * final block's BFINAL bit, zeroes the bits after its end and appends an
 * empty stored block. z must have room for DEFLATE_UNFINAL_EXTRA more
 * bytes; *n grows by 4 or 5. */
void deflate_unfinal(uint8_t *z, size_t *n, const deflate_ends *ends);

/* The Adler-32 of A followed by B, from adler(A), adler(B) and B's length. */
uint32_t deflate_adler32_combine(uint32_t a, uint32_t b, size_t len_b);

#endif
