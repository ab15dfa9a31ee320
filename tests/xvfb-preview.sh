#!/bin/sh
# Drives the preview window under a private Xvfb for tests/test_preview.c.
# Usage: tests/xvfb-preview.sh MODE DIR GLINT [glint options...]
#   final  glint -p --exit-when-done: screenshot of the final image, then close
#   orbit  glint -p: screenshot, a left-drag orbit, screenshot, P, Esc
#   watch  glint -p: screenshot, runs $EDIT1 (a change to the scene's files),
#          screenshot of the reloaded scene, runs $EDIT2 (a mistake), waits
#          for the error line, screenshot, Esc
# Leaves in DIR: log (glint's stderr), out (its stdout), code (its exit
# status), geometry (window X Y W H), screen1.ppm [screen2.ppm].
set -u
# Under AddressSanitizer, leaks are not checked here: the system libraries
# behind SDL's window (D-Bus, loaded and unloaded at run time) keep memory
# until exit that LeakSanitizer cannot name, let alone suppress. Every other
# run of glint in the suite checks for leaks.
ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
export ASAN_OPTIONS
mode=$1 dir=$2 glint=$3
shift 3
cd "$dir" || exit 1

Xvfb -displayfd 1 -screen 0 800x600x24 -nolisten tcp > display 2> xvfb.log &
xvfb=$!
trap 'kill $xvfb 2>/dev/null; wait $xvfb 2>/dev/null' EXIT
i=0
while [ ! -s display ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
DISPLAY=:$(cat display)
export DISPLAY

# waits until the log has N lines containing $2 (at most a minute)
wait_log() {
    i=0
    while n=$(grep -c "$2" log 2>/dev/null); [ "${n:-0}" -lt "$1" ] && [ $i -lt 600 ]; do
        sleep 0.1
        i=$((i + 1))
    done
}

shot() {
    sleep 0.2
    xwd -root -silent | xwdtopnm > "$1" 2> /dev/null
}

geometry() {
    # at most a minute: a window that never opens fails the test, not hangs it
    id=$(timeout 60 xdotool search --sync --name '^glint' | head -n 1)
    xdotool getwindowgeometry --shell "$id" > geo.sh
    . ./geo.sh
    echo "$X $Y $WIDTH $HEIGHT" > geometry
}

case "$mode" in
final)
    GLINT_TEST_REPORT=1 GLINT_TEST_HOLD_FILE="$dir/hold" "$glint" -p --exit-when-done "$@" \
        > out 2> log &
    pid=$!
    wait_log 1 'preview: final image'
    geometry
    shot screen1.ppm
    touch hold
    ;;
orbit)
    GLINT_TEST_REPORT=1 "$glint" -p "$@" > out 2> log &
    pid=$!
    wait_log 1 'preview: final image'
    geometry
    shot screen1.ppm
    cx=$((X + WIDTH / 2)) cy=$((Y + HEIGHT / 2))
    xdotool mousemove $cx $cy mousedown 1
    for step in 1 2 3 4 5 6 7 8; do
        xdotool mousemove $((cx + step * 8)) $((cy + step * 2))
        sleep 0.05
    done
    xdotool mouseup 1
    wait_log 2 'preview: final image'
    shot screen2.ppm
    xdotool key p
    sleep 0.3
    xdotool key Escape
    ;;
watch)
    GLINT_TEST_REPORT=1 "$glint" -p "$@" > out 2> log &
    pid=$!
    wait_log 1 'preview: final image'
    geometry
    shot screen1.ppm
    sleep 1.1 # a new modification time even on coarse clocks
    sh -c "$EDIT1"
    wait_log 2 'preview: final image'
    shot screen2.ppm
    sleep 1.1
    sh -c "$EDIT2"
    wait_log 1 'glint: .*yaml:'
    sleep 0.5
    shot screen3.ppm
    xdotool key Escape
    ;;
esac
i=0
while kill -0 $pid 2>/dev/null && [ $i -lt 300 ]; do sleep 0.1; i=$((i + 1)); done
wait $pid
echo $? > code
