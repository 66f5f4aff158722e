#!/bin/bash
# What a user waits for in the window, for raylab binaries in turn (interleaved), driven with
# real X input on the X display $DISPLAY (a 1280x800 screen: `Xvfb :7 -screen 0 1280x800x24 &`):
#   open:  a scene placing meshes typed into the path field and Entered while the cracks of
#          cramer's 3x3 frame of the Cornell box are counted: ms from Return to "loaded"
#   next:  N (next crack) with cramer's 2x2 cracks of the box counted: ms to "crack 1 of"
# Usage: DISPLAY=:7 benches/window_waits.sh RUNS BINARY...
set -u
runs=$1
shift
# (The window is found by its title: another raylab on the display would be driven instead.)
if xdotool search --name '^raylab' >/dev/null 2>&1; then
    echo "a raylab window is open on $DISPLAY already: close it first" >&2
    exit 2
fi
work=$(mktemp -d)
trap 'kill $(cat "$work/app.pid" 2>/dev/null) 2>/dev/null; rm -rf "$work"' EXIT
cd "$work" || exit 1
cat > pyramid.obj <<'EOF'
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 2 3
f 1 2 4
f 1 3 4
f 2 3 4
EOF
printf 'cornell\npush\ntranslate 0 0.5 0\nscale 0.3\nmesh pyramid.obj\npop\n' > placed.scene
printf 'scene cornell\nmethod cramer\ncracks on\nsize 784 698\nspp 3\n' > cramer3.view

now_ms() { echo $(($(date +%s%N) / 1000000)); }
# waits (20 s at most) for TEXT in the app's log
logged() { for _ in $(seq 400); do grep -q -- "$1" app.log && return 0; sleep 0.05; done; return 1; }
start() {
    kill $(cat app.pid 2>/dev/null) 2>/dev/null
    sleep 1
    RUST_LOG=info,raylab_app=debug "$@" > /dev/null 2> app.log &
    echo $! > app.pid
    logged 'first image on screen'
    win=$(xdotool search --name '^raylab' | head -1)
    xdotool windowfocus --sync "$win"
}

open_ms() {
    start "$1" cramer3.view
    logged 'counted the cracks of frame .* 3x3' || return
    # W moves the camera: the new view refines and its cracks are counted as the file opens.
    xdotool mousemove --sync 700 400 keydown w
    sleep 0.3
    xdotool keyup w
    sleep 0.8
    xdotool mousemove --sync 150 683 click 1 key ctrl+a BackSpace
    xdotool type --delay 5 placed.scene
    local t0
    t0=$(now_ms)
    xdotool key Return
    logged 'loaded placed.scene' && echo $(($(now_ms) - t0))
}

next_ms() {
    start "$1"
    # "show cracks", then cramer from the method list (the panel at the default window).
    xdotool mousemove --sync 15 571 click 1
    sleep 1
    xdotool mousemove --sync 57 550 click 1
    sleep 1
    xdotool mousemove --sync 40 638 click 1
    logged 'counted the cracks of frame .* 2x2 samples a pixel) in [1-9]' || return
    sleep 2
    xdotool mousemove --sync 700 400
    local t0
    t0=$(now_ms)
    xdotool key n
    logged 'crack 1 of' && echo $(($(now_ms) - t0))
}

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2) ($(nproc) cores)"
echo "run | binary | open ms | next ms"
for run in $(seq "$runs"); do
    for binary in "$@"; do
        echo "$run | $binary | $(open_ms "$binary") | $(next_ms "$binary")"
    done
done
