# glint build. `make run` and `make test` are the two entry points (README.md).
#
# Variants build into their own folder: build/ (optimised) and build/asan/
# (AddressSanitizer + UBSan, used by `make test`). Every .c under src/ goes
# into the library except the command lines: src/app (glint), src/dist
# (glint-mpi) and src/cli (what both take from the command line): the
# static libglint.a and the shared libglint.so, which exports only the
# glint_* functions of include/glint.h (hidden visibility by default, and
# the export list in src/api/glint.map).

BUILD    ?= build
SAN      ?= 0
CC       ?= cc
PKGS     := yaml-0.1 stb assimp spng libjpeg libdeflate libisal
# Only libyaml and libdeflate are linked. The others, and OpenEXR's C
# library (OpenEXRCore alone, not its C++ ones), are opened when first
# needed (src/core/dynlib.h): assimp at the first mesh import, libjpeg,
# OpenEXRCore, stb_image and libspng at the first image of theirs read or
# written, ISA-L at the first noisy PNG strip. They are compiled against
# their headers, and the dynamic loader maps none of them at start.
LAZY_PKGS := stb assimp spng libjpeg libisal
LINK_PKGS := $(filter-out $(LAZY_PKGS),$(PKGS))
EXR_CFLAGS := $(shell pkg-config --cflags OpenEXR 2>/dev/null)
EXR_LINK   := $(filter -lOpenEXRCore%,$(shell pkg-config --libs OpenEXR 2>/dev/null))
EXR_LIB    := $(patsubst -l%,lib%,$(or $(EXR_LINK),-lOpenEXRCore-3_1))

# The names the opened libraries are looked up by, as
# -DGLINT_SONAME_JPEG='"libjpeg.so.62"': the soname of the development
# link the linker would have taken (libjpeg.so -> libjpeg.so.62), or where
# that cannot be read, Debian 12's.
soname_of = $(shell f=$$($(CC) -print-file-name=$(1).so 2>/dev/null) && \
              readelf -d "$$f" 2>/dev/null | sed -n 's/.*(SONAME).*\[\(.*\)\]$$/\1/p')
soname_flag = -DGLINT_SONAME_$(1)='"$(or $(call soname_of,$(2)),$(3))"'
SONAME_FLAGS := $(call soname_flag,JPEG,libjpeg,libjpeg.so.62) \
                $(call soname_flag,EXR,$(EXR_LIB),libOpenEXRCore-3_1.so.30) \
                $(call soname_flag,STB,libstb,libstb.so.0) \
                $(call soname_flag,SPNG,libspng,libspng.so.0) \
                $(call soname_flag,ISAL,libisal,libisal.so.2) \
                $(call soname_flag,ASSIMP,libassimp,libassimp.so.5)

CPPFLAGS := -Iinclude -Isrc -I$(BUILD)/gen -D_DEFAULT_SOURCE \
            $(shell pkg-config --cflags $(PKGS) 2>/dev/null) $(EXR_CFLAGS) $(SONAME_FLAGS)
CFLAGS   := -std=c11 -fno-math-errno -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes -Wswitch-enum -Werror=implicit-function-declaration -g -pthread
ifeq ($(SAN),1)
CFLAGS   += -O1 -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
LDFLAGS  += -fsanitize=address,undefined
else ifeq ($(SAN),fuzz)
CFLAGS   += -O1 -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
LDFLAGS  += -fsanitize=fuzzer,address,undefined
else
CFLAGS   += -O2
endif
LDLIBS   := $(shell pkg-config --libs $(LINK_PKGS) 2>/dev/null) -lm -pthread -ldl
# The tests and tools write and check images with stb_image_write and
# libspng themselves (make textures with stb_perlin): linked to them.
STB_LIBS  := $(or $(shell pkg-config --libs stb 2>/dev/null),-lstb)
SPNG_LIBS := $(or $(shell pkg-config --libs spng 2>/dev/null),-lspng)

# The command line opens SDL2 for its preview window (-p) when the window
# opens (src/app/sdl_load.c), so it is compiled against SDL2's headers but
# not linked to it: only src/app includes it, and the library does not
# depend on it.
SDL_CFLAGS := $(shell pkg-config --cflags sdl2 2>/dev/null)

LIB_SRC  := $(shell find src -name '*.c' -not -path 'src/app/*' -not -path 'src/dist/*' \
              -not -path 'src/cli/*' | sort)
APP_SRC  := $(wildcard src/app/*.c)
CLI_SRC  := $(wildcard src/cli/*.c)
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/obj/%.o)
TEST_SRC := $(wildcard tests/test_*.c)
GEN_SRC  := $(BUILD)/gen/assets.c
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/obj/%.o) $(BUILD)/obj/gen/assets.o
APP_OBJ  := $(APP_SRC:%.c=$(BUILD)/obj/%.o)
TEST_OBJ := $(TEST_SRC:%.c=$(BUILD)/obj/%.o)
DIST_SRC := $(wildcard src/dist/*.c)
DIST_OBJ := $(DIST_SRC:%.c=$(BUILD)/obj/%.o)
DEPS     := $(LIB_OBJ:.o=.d) $(APP_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(DIST_OBJ:.o=.d) $(CLI_OBJ:.o=.d)

# glint-mpi (src/dist, the only code that includes mpi.h) is built whenever
# Open MPI's compiler wrapper is there; its flags, with the compiler above.
MPICC      ?= mpicc
HAVE_MPI   := $(shell command -v $(MPICC) >/dev/null 2>&1 && echo yes)
MPI_CFLAGS := $(if $(HAVE_MPI),$(shell $(MPICC) --showme:compile 2>/dev/null))
MPI_LIBS   := $(if $(HAVE_MPI),$(shell $(MPICC) --showme:link 2>/dev/null))
MPI_BIN    := $(if $(HAVE_MPI),$(BUILD)/glint-mpi)

.PHONY: all deps run test check clean fuzz
.DEFAULT_GOAL := all

all: deps
	@$(MAKE) --no-print-directory $(BUILD)/glint $(BUILD)/libglint.a $(BUILD)/libglint.so \
		$(MPI_BIN) scenes/textures/flag.png scenes/textures/globe.png

deps:
	@scripts/install-deps build

run: all
	$(BUILD)/glint -o glint.png

# The full suite: optimised build, then again under ASan + UBSan, each
# built on every core.
NPROC := $(shell nproc 2>/dev/null || echo 2)
test:
	@scripts/install-deps test
	@$(MAKE) --no-print-directory -j$(NPROC) check
	@$(MAKE) --no-print-directory -j$(NPROC) BUILD=build/asan SAN=1 check

check: $(BUILD)/glint $(MPI_BIN) $(BUILD)/tests scenes/textures/flag.png scenes/textures/globe.png
	scripts/check-layers
	scripts/check-size
	GLINT_BIN=$(BUILD)/glint GLINT_MPI_BIN=$(MPI_BIN) ASAN_OPTIONS=detect_leaks=1 \
		LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan-criterion.supp \
		UBSAN_OPTIONS=print_stacktrace=1 $(BUILD)/tests --jobs 2
ifeq ($(SAN),0)
	@$(MAKE) --no-print-directory check-lib check-bench
endif

# The benchmark programs compile against today's library (make bench
# builds them; this catches a changed signature without running them).
# Those of output.c and raybench.c need libpng's and Embree's headers,
# which `install-deps bench` brings: compiled when they are there.
BENCH_CHECK := spheres interactive $(if $(wildcard /usr/include/png.h),output) \
               $(if $(wildcard /usr/include/embree3/rtcore.h),raybench)
$(BUILD)/obj/bench/%.o: CFLAGS += -Werror
.PHONY: check-bench
check-bench: $(BENCH_CHECK:%=$(BUILD)/obj/bench/%.o)
	@echo "check-bench: compiled bench/ ($(BENCH_CHECK))"

# The library as users get it: only glint_* exported, and a program built
# against the installed header and glint.pc (shared and static) that runs.
.PHONY: check-lib
check-lib: $(BUILD)/libglint.so
	scripts/check-exports $(BUILD)/libglint.so
	@rm -rf $(BUILD)/stage
	@$(MAKE) --no-print-directory install PREFIX=$(CURDIR)/$(BUILD)/stage >/dev/null
	BUILD=$(BUILD) CC=$(CC) scripts/check-install $(CURDIR)/$(BUILD)/stage

# `make install PREFIX=/usr/local DESTDIR=`: the command (and glint-mpi when built), both libraries,
# the header, glint.pc, the example scenes and the documentation. glint.pc
# names the static library's dependencies: the linked pkg-config packages
# (libyaml, libdeflate), libm, threads and libdl; the libraries opened at
# run time are not needed to link.
PREFIX  ?= /usr/local
DESTDIR ?=
INSTALL_LIB := $(DESTDIR)$(PREFIX)/lib
INSTALL_DOC := $(DESTDIR)$(PREFIX)/share/doc/glint
.PHONY: install
install: all
	@mkdir -p $(BUILD)
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(VERSION)|' -e 's|@REQUIRES@|$(LINK_PKGS)|' \
		-e 's|@LIBS_PRIVATE@|-lm -pthread -ldl|' src/api/glint.pc.in > $(BUILD)/glint.pc
	install -d $(DESTDIR)$(PREFIX)/bin $(INSTALL_LIB)/pkgconfig $(DESTDIR)$(PREFIX)/include \
		$(DESTDIR)$(PREFIX)/share/glint $(INSTALL_DOC)
	install -m 755 $(BUILD)/glint $(DESTDIR)$(PREFIX)/bin/glint
	$(if $(MPI_BIN),install -m 755 $(MPI_BIN) $(DESTDIR)$(PREFIX)/bin/glint-mpi)
	install -m 644 $(BUILD)/libglint.a $(INSTALL_LIB)/libglint.a
	install -m 755 $(BUILD)/libglint.so $(INSTALL_LIB)/libglint.so.$(VERSION)
	ln -sf libglint.so.$(VERSION) $(INSTALL_LIB)/libglint.so.$(SOVERSION)
	ln -sf libglint.so.$(SOVERSION) $(INSTALL_LIB)/libglint.so
	install -m 644 include/glint.h $(DESTDIR)$(PREFIX)/include/glint.h
	install -m 644 $(BUILD)/glint.pc $(INSTALL_LIB)/pkgconfig/glint.pc
	cp -R scenes $(DESTDIR)$(PREFIX)/share/glint/
	install -m 644 README.md docs/*.md $(INSTALL_DOC)/

# The eight-wide traversal kernels (src/accel/isa.h): files named *_avx2.c
# and *_avx512.c are compiled for those instruction sets and only run where
# the CPU has them. No contraction into FMA anywhere, so that every path
# rounds the same way and images stay byte-identical across paths. Both
# kinds of kernel work in 256-bit registers, and their block moves are
# capped at 256 bits too: else GCC copies a packet's fields in moves that
# do not match the stores which wrote them, and each load waits for those
# stores to reach the cache (a store-forwarding stall). Uncapped, the
# AVX-512 kernels copied two adjacent 32-byte arrays in one 64-byte move
# (light8_point and prepare spent 2-3% of a frame there), and the AVX2
# kernels, under GCC's generic tuning, copied them 16 bytes at a time and
# read them back 32 (light8_point, bounce and split: the AVX2 path's
# frames took 13% longer than the AVX-512 path's; GCC's options: clang,
# which `make fuzz` uses, has no such cap and goes without).
CC_IS_CLANG := $(if $(shell $(CC) --version 2>/dev/null | grep -i clang),1,)
ifneq ($(filter x86_64%,$(shell $(CC) -dumpmachine)),)
KERNEL_MOVES        := $(if $(CC_IS_CLANG),,-mmove-max=256 -mstore-max=256)
KERNEL_FLAGS_avx2   := -mavx2 -ffp-contract=off $(KERNEL_MOVES)
KERNEL_FLAGS_avx512 := -mavx2 -mavx512f -mavx512vl -ffp-contract=off $(KERNEL_MOVES)
$(BUILD)/obj/src/%_avx2.o: CFLAGS += $(KERNEL_FLAGS_avx2)
$(BUILD)/obj/src/%_avx512.o: CFLAGS += $(KERNEL_FLAGS_avx512)
endif

# Library objects serve both libraries: position-independent, and hidden
# unless glint.h marks them GLINT_API.
LIB_CFLAGS := -fPIC -fvisibility=hidden
$(LIB_OBJ): CFLAGS += $(LIB_CFLAGS)

# Profile-guided optimisation of the optimised build (PGO=1, the default
# with GCC; `make PGO=0 BUILD=build/quick` builds without it, in a folder
# of its own so that the two kinds of object never mix). The library and
# the commands are first built instrumented into $(BUILD)/pgo
# (PGO=generate), which renders the training set (scripts/pgo-train: the
# built-in scene, every scenes/*.yaml and a generated field of 4,096
# objects, small, on one thread); the
# counts that run leaves are put beside the objects here (<object>.gcda),
# which are then compiled with them. Floats are worked out the same either
# way: only where the code branches, inlines and is laid out changes. A
# source or scene newer than the profile starts the round again.
ifeq ($(origin PGO),undefined)
PGO := $(if $(CC_IS_CLANG),0,1)
endif
# The tree builders (src/accel) are compiled without the counts: the
# training builds only small trees, and with their counts GCC optimised the
# builders for size (10^6 random spheres built 9% slower than without).
PGO_UNTRAINED := $(BUILD)/obj/src/accel/%
PGO_OBJ := $(filter-out $(PGO_UNTRAINED),$(LIB_OBJ)) $(APP_OBJ) $(CLI_OBJ)
# (a static function's counts are found by its number in its file, not
# by a name made from the object's path, which differs between the rounds)
PGO_IDS := --param=profile-func-internal-id=1
ifeq ($(SAN)$(PGO),0generate)
CFLAGS  += -fprofile-generate -fprofile-update=single $(PGO_IDS)
LDFLAGS += -fprofile-generate
else ifeq ($(SAN),0)
ifneq ($(PGO),0)
PGO_USE_FLAGS := -fprofile-use -fprofile-partial-training $(PGO_IDS) -Wno-missing-profile
$(PGO_OBJ): CFLAGS += $(PGO_USE_FLAGS)
$(PGO_OBJ): $(BUILD)/pgo.stamp
$(BUILD)/pgo.stamp: $(BUILD)/flags.stamp \
                    $(LIB_SRC) $(APP_SRC) $(CLI_SRC) $(shell find src include -name '*.h') \
                    $(shell find scenes -type f) scripts/pgo-train scripts/pgo-field.awk \
                    scenes/textures/flag.png scenes/textures/globe.png
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/pgo PGO=generate $(BUILD)/pgo/glint
	scripts/pgo-train $(BUILD)/pgo $(BUILD)
	@touch $@
endif
endif

$(BUILD)/libglint.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

VERSION   := $(shell sed -n 's/^\#define GLINT_VERSION "\(.*\)"/\1/p' include/glint.h)
SOVERSION := $(firstword $(subst ., ,$(VERSION)))

$(BUILD)/libglint.so: $(LIB_OBJ) src/api/glint.map
	$(CC) $(CFLAGS) $(LDFLAGS) -shared -Wl,-soname,libglint.so.$(SOVERSION) \
		-Wl,--version-script=src/api/glint.map -Wl,--no-undefined -o $@ $(LIB_OBJ) $(LDLIBS)

$(APP_OBJ): CPPFLAGS += $(SDL_CFLAGS)

$(BUILD)/glint: $(APP_OBJ) $(CLI_OBJ) $(BUILD)/libglint.a
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/glint-mpi: $(DIST_OBJ) $(CLI_OBJ) $(BUILD)/libglint.a
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS) $(MPI_LIBS)

$(DIST_OBJ): CPPFLAGS += $(MPI_CFLAGS)

# The library's allocations pass through tests/test_alloc.c, which makes
# each fail in turn. The tests take the scheduler of glint-mpi too (it has
# no MPI in it) and the programs' heap policy (src/cli/heap.c).
TEST_WRAP := -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=aligned_alloc
$(BUILD)/tests: $(TEST_OBJ) $(BUILD)/obj/src/dist/sched.o $(BUILD)/obj/src/cli/heap.o $(BUILD)/libglint.a
	$(CC) $(CFLAGS) $(LDFLAGS) $(TEST_WRAP) -o $@ $^ $(LDLIBS) $(STB_LIBS) $(SPNG_LIBS) -lcriterion

$(BUILD)/obj/tests/%.o: CPPFLAGS += -DGLINT_SOURCE_DIR='"$(CURDIR)"'

# Objects are made again when the flags they are compiled with change (an
# edit of the flags here, or flags given on make's command line), not only
# when their sources do: $(BUILD)/flags.stamp holds the flags of the last
# make in that folder, compared and rewritten while this file is read
# (expanded once, here: a prerequisite would otherwise see the flags of
# whichever object asked for it first; and no rule that always runs, so
# `make -n` and `make -q` still say what is out of date).
FLAGS_NOW := $(CC) $(CPPFLAGS) $(CFLAGS) | $(LIB_CFLAGS) | $(SDL_CFLAGS) | $(MPI_CFLAGS) | \
             $(KERNEL_FLAGS_avx2) | $(KERNEL_FLAGS_avx512) | $(PGO_USE_FLAGS) | \
             untrained: $(PGO_UNTRAINED) | PGO=$(PGO) SAN=$(SAN) | $(CURDIR)
ifneq ($(strip $(file <$(BUILD)/flags.stamp)),$(strip $(FLAGS_NOW)))
$(shell mkdir -p $(BUILD))
$(file >$(BUILD)/flags.stamp,$(FLAGS_NOW))
endif
BENCH_OBJ := $(patsubst bench/%.c,$(BUILD)/obj/bench/%.o,$(wildcard bench/*.c))
$(LIB_OBJ) $(APP_OBJ) $(CLI_OBJ) $(TEST_OBJ) $(DIST_OBJ) $(BENCH_OBJ): $(BUILD)/flags.stamp

$(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c -o $@ $<

$(BUILD)/obj/gen/assets.o: $(GEN_SRC)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

# Built-in textures: made by tools/mktextures, embedded by tools/embed.
$(BUILD)/tools/%: tools/%.c
	@mkdir -p $(dir $@)
	$(CC) -std=c11 -O2 -Wall -Wextra $(CPPFLAGS) -o $@ $< $(LDLIBS) $(STB_LIBS)

$(BUILD)/gen/flag.png $(BUILD)/gen/globe.png &: $(BUILD)/tools/mktextures
	@mkdir -p $(BUILD)/gen
	$(BUILD)/tools/mktextures $(BUILD)/gen

# The example scenes in scenes/ use the same two pictures from disk.
scenes/textures/%.png: $(BUILD)/gen/%.png
	@mkdir -p $(dir $@)
	cp $< $@

# The built-in scene is scenes/seed.yaml with the two textures it names.
$(GEN_SRC): $(BUILD)/tools/embed scenes/seed.yaml $(BUILD)/gen/flag.png $(BUILD)/gen/globe.png
	$(BUILD)/tools/embed $@ seed.yaml=scenes/seed.yaml \
		textures/flag.png=$(BUILD)/gen/flag.png textures/globe.png=$(BUILD)/gen/globe.png

# Coverage-guided fuzzing with libFuzzer (clang):
# `make fuzz [TARGET=scene|texture|mesh] FUZZ_SECONDS=1800`. Target T is
# fuzz/fuzz_T.c; its seeds and dictionary are FUZZ_ARGS_T, extra libFuzzer
# flags FUZZ_FLAGS_T. New inputs collect in build/fuzz/corpus-T
# (build/fuzz/corpus for the scene loader); crashes are written to
# build/fuzz/ as crash-* files. The mesh target runs with -fork=1 and keeps
# going after a crash, timeout or OOM (assimp's own faults are what the
# child process contains); each one still leaves its file.
FUZZ_SECONDS ?= 60
TARGET ?= scene
FUZZ_CORPUS_scene   := corpus
FUZZ_ARGS_scene     := -dict=../../fuzz/yaml.dict ../../scenes ../../scenes/parts
FUZZ_PREP_texture   := fuzz-seeds-texture
FUZZ_ARGS_texture   := -dict=../../fuzz/image.dict seeds-texture
FUZZ_PREP_mesh      := fuzz-seeds-mesh
FUZZ_ARGS_mesh      := seeds-mesh
FUZZ_FLAGS_mesh     := -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1
FUZZ_ENV_mesh       := LSAN_OPTIONS=suppressions=../../fuzz/mesh.lsan ASAN_OPTIONS=symbolize=0
fuzz:
	@scripts/install-deps fuzz
	@test -f fuzz/fuzz_$(TARGET).c || { echo "make fuzz: no target fuzz/fuzz_$(TARGET).c" >&2; exit 2; }
	@$(MAKE) --no-print-directory BUILD=build/fuzz SAN=fuzz CC=clang build/fuzz/fuzz_$(TARGET)
	@$(MAKE) --no-print-directory $(FUZZ_PREP_$(TARGET))
	@mkdir -p build/fuzz/$(or $(FUZZ_CORPUS_$(TARGET)),corpus-$(TARGET))
	cd build/fuzz && $(FUZZ_ENV_$(TARGET)) ./fuzz_$(TARGET) -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 \
		$(FUZZ_FLAGS_$(TARGET)) $(or $(FUZZ_CORPUS_$(TARGET)),corpus-$(TARGET)) $(FUZZ_ARGS_$(TARGET))

$(BUILD)/fuzz_%: $(BUILD)/obj/fuzz/fuzz_%.o $(BUILD)/libglint.a
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS)

# Seeds for the texture target: one small file per format, made by the
# optimised build's writers (tools/fuzzseeds.c).
.PHONY: fuzz-seeds-texture
fuzz-seeds-texture: build/tools/fuzzseeds
	@mkdir -p build/fuzz/seeds-texture
	build/tools/fuzzseeds build/fuzz/seeds-texture

# Seeds for the mesh target: the test meshes in fuzz/seeds-mesh, each behind
# the byte that names its format in fuzz/fuzz_mesh.c (its place in names[]).
.PHONY: fuzz-seeds-mesh
fuzz-seeds-mesh:
	@mkdir -p build/fuzz/seeds-mesh
	@for f in fuzz/seeds-mesh/*; do \
		case "$$f" in *.ply) b=000;; *.obj) b=001;; *.off) b=002;; *.stl) b=003;; \
		*.gltf) b=004;; *.glb) b=005;; *.dae) b=006;; *.3ds) b=007;; *.fbx) b=010;; \
		*.x) b=011;; *.ac) b=012;; *.3mf) b=013;; *) continue;; esac; \
		{ printf "\\$$b"; cat "$$f"; } > build/fuzz/seeds-mesh/$$(basename "$$f"); \
	done

build/tools/fuzzseeds: tools/fuzzseeds.c build/libglint.a
	@mkdir -p $(dir $@)
	$(CC) -std=c11 -O2 -Wall -Wextra $(CPPFLAGS) -o $@ $^ $(LDLIBS) $(STB_LIBS)

# Benchmarks against POV-Ray and Embree, results in bench/RESULTS.md
# (bench/README.md: what each row measures, settings such as BENCH_RUNS,
# running one row alone). Always the optimised build.
.PHONY: bench
EMBREE_LIBS = $(shell pkg-config --libs embree3 2>/dev/null || echo -lembree3)
bench:
	@scripts/install-deps bench
	@$(MAKE) --no-print-directory SAN=0 $(BUILD)/glint $(BUILD)/bench/spheres $(BUILD)/bench/raybench \
		$(BUILD)/bench/output $(BUILD)/bench/interactive scenes/textures/flag.png scenes/textures/globe.png
	BUILD=$(BUILD) bench/run

$(BUILD)/bench/spheres: $(BUILD)/obj/bench/spheres.o $(BUILD)/libglint.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/bench/interactive: $(BUILD)/obj/bench/interactive.o $(BUILD)/libglint.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/bench/output: $(BUILD)/obj/bench/output.o $(BUILD)/libglint.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS) $(shell pkg-config --libs libpng 2>/dev/null || echo -lpng)

$(BUILD)/bench/raybench: $(BUILD)/obj/bench/raybench.o $(BUILD)/libglint.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS) $(EMBREE_LIBS)

-include $(wildcard $(BUILD)/obj/bench/*.d)

clean:
	rm -rf build glint.png

-include $(DEPS)

# Scaling across processes (bench/README.md, "Across processes"): the
# scheduler simulator, then bench/mpi measures and simulates.
$(BUILD)/bench/mpisim: bench/mpisim.c src/dist/sched.c src/dist/sched.h src/dist/job.h
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -o $@ bench/mpisim.c src/dist/sched.c

.PHONY: bench-mpi
bench-mpi:
	@scripts/install-deps test bench
	@$(MAKE) --no-print-directory SAN=0 $(BUILD)/glint $(BUILD)/glint-mpi $(BUILD)/bench/mpisim \
		scenes/textures/flag.png scenes/textures/globe.png
	BUILD=$(BUILD) bench/mpi
