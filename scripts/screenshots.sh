#!/usr/bin/env bash
# Regenerates the README's screenshots (assets/screenshots/*.png) from real recordings.
#
#   scripts/screenshots.sh            # every picture
#   scripts/screenshots.sh contact    # only the named ones (names as in the list at the bottom)
#
# Each picture: the kecsim command writes a recording (.rrd) into a scratch directory, a headless
# Rerun viewer (`rerun --headless`, the CLI of rerun-sdk 0.36.3) opens it, and after a delay (so
# that the whole file is loaded and the start-up notifications have faded) a screenshot is asked
# for over the viewer's gRPC port with `rerun.experimental.ViewerClient.save_screenshot` — the
# CLI's own `--screenshot-to` has no delay and takes the first frame. PNGs are saved with
# a 256-colour palette, and made smaller only where that is still over ~300 KB (python3 with PIL).
#
# Needs: a release build (`cargo build --release`), `rerun` 0.36.3 and its Python package on
# PATH, Vulkan (Mesa's lavapipe will do: `apt-get install -y mesa-vulkan-drivers libvulkan1`).
# Takes ~10 minutes on 2 cores (the default run's kilometre and the study dominate).
set -euo pipefail
cd "$(dirname "$0")/.."

KECSIM="${KECSIM:-target/release/kecsim}"
OUT="${OUT:-assets/screenshots}"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
export KECSIM_CACHE_DIR="$WORK/cache"   # a cold cache: the pictures do not hang on old tables
export XDG_RUNTIME_DIR="$WORK/xdg"
mkdir -p "$XDG_RUNTIME_DIR" "$OUT"
chmod 700 "$XDG_RUNTIME_DIR"
PORT="${PORT:-9877}"

[ -x "$KECSIM" ] || { echo "no $KECSIM: run cargo build --release first" >&2; exit 1; }
command -v rerun >/dev/null || { echo "no rerun on PATH: pip install rerun-sdk==0.36.3" >&2; exit 1; }

# shot NAME RRD [DELAY_S] [WIDTHxHEIGHT]: screenshot of RRD in the headless viewer as OUT/NAME.png
shot() {
  local name="$1" rrd="$2" delay="${3:-10}" size="${4:-1600x1000}"
  # its own process group (`rerun` may be a wrapper around the viewer's binary), so that the
  # whole of it ends below and the next viewer does not hand its file to this one
  setsid rerun --headless --window-size "$size" --port "$PORT" "$rrd" >"$WORK/viewer-$name.log" 2>&1 &
  local viewer=$!
  sleep "$delay"
  python3 - "rerun+http://127.0.0.1:$PORT/proxy" "$WORK/$name.png" <<'EOF'
import sys, time
from rerun.experimental import ViewerClient
url, out = sys.argv[1], sys.argv[2]
for attempt in range(30):
    try:
        ViewerClient.connect(url).save_screenshot(out)
        break
    except Exception as e:  # the viewer's port not open yet
        last = e
        time.sleep(1)
else:
    sys.exit(f"no screenshot from {url}: {last}")
EOF
  sleep 2
  kill -- -"$viewer" 2>/dev/null || true
  wait "$viewer" 2>/dev/null || true
  sleep 1
  python3 - "$WORK/$name.png" "$OUT/$name.png" <<'EOF'
import os, sys
from PIL import Image
src, dst = sys.argv[1], sys.argv[2]
full = Image.open(src).convert("RGB")
# a screenshot of the viewer has few colours: a 256-colour palette keeps it legible at a
# fraction of the size; only if that is still over ~300 KB is it made smaller
im, width = full, full.width
while True:
    im.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(dst, optimize=True)
    if os.path.getsize(dst) <= 300_000 or width <= 1000:
        break
    width = int(width * 0.875)
    im = full.resize((width, round(full.height * width / full.width)), Image.LANCZOS)
print(f"{dst}: {Image.open(dst).size}, {os.path.getsize(dst) // 1000} KB")
EOF
}

k() { echo "+ kecsim $*" >&2; "$KECSIM" "$@" >"$WORK/last.log" 2>&1 || { cat "$WORK/last.log" >&2; return 1; }; }

# The README's example of each command, writing into the scratch directory.
profiles()     { k profiles --wheel s1002 --rail 60e1 --inclination 1:40 --save "$WORK/p.rrd"; shot profiles "$WORK/p.rrd"; }
contact()      { k contact --csv "$WORK/table.csv" --save "$WORK/c.rrd"; shot contact "$WORK/c.rrd"; }
kec()          { k kec --accuracy --save "$WORK/k.rrd"; shot kec "$WORK/k.rrd"; }
design_wheel() { k design-wheel --csv "$WORK/ms-tram.csv" --reference ms-standin --save "$WORK/d.rrd"; shot design_wheel "$WORK/d.rrd"; }
patch()        { k patch --wheel s1002 --rail 60e1 --inclination 1:40 --y-mm 0,-1,-2,-3,-4,-5,-5.5,-6,-6.5,-7,-8,-10 --yaw-per-mm 2.4 --load-n 10000 --save "$WORK/pa.rrd"; shot patch "$WORK/pa.rrd"; }
creep()        { k creep --normal-force-n 80000 --a-mm 6 --b-mm 4 --spin 1 --save "$WORK/cr.rrd"; shot creep "$WORK/cr.rrd"; }
track()        { k track assets/track/tab6_irregular.toml --csv "$WORK/track.csv" --save "$WORK/t.rrd"; shot track "$WORK/t.rrd"; }
run()          { k run --csv "$WORK/out" --json "$WORK/summary.json" --save "$WORK/r.rrd"; shot run "$WORK/r.rrd" 30; }
# the same run's "Forces and safety" tab: the running-safety series with their limits
run_safety()   { k run --tab forces --save "$WORK/rs.rrd"; shot run_safety "$WORK/rs.rrd" 30; }
# the default scene's first 12 s: the tram in its curve (the 3D view, the running bands)
run_curve()    { sed 's/^duration_s = 51.0 /duration_s = 12.0 /' assets/scenes/ms_vehicle_tab6.toml >"$WORK/ms12.toml"
                 k run "$WORK/ms12.toml" --save "$WORK/rc.rrd"; shot run_curve "$WORK/rc.rrd" 15; }
# the default run streamed live to a headless viewer (--connect --pace 1), two pictures 6 s of wall
# time apart while it computes (docs/cli.md, "Watching a run live")
live() {
  setsid rerun --headless --window-size 1600x1000 --port "$PORT" >"$WORK/viewer-live.log" 2>&1 &
  local viewer=$!
  sleep 10
  "$KECSIM" run --connect "rerun+http://127.0.0.1:$PORT/proxy" --pace 1 >"$WORK/live.log" 2>&1 &
  local run=$!
  for k in 1 2; do
    sleep "$([ "$k" = 1 ] && echo 12 || echo 6)"
    python3 - "rerun+http://127.0.0.1:$PORT/proxy" "$WORK/live_run_$k.png" <<'EOF2'
import sys
from rerun.experimental import ViewerClient
ViewerClient.connect(sys.argv[1]).save_screenshot(sys.argv[2])
EOF2
    python3 -c "
import sys
from PIL import Image
Image.open(sys.argv[1]).convert('RGB').quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(sys.argv[2], optimize=True)
print(sys.argv[2])" "$WORK/live_run_$k.png" "$OUT/live_run_$k.png"
  done
  kill "$run" 2>/dev/null || true
  wait "$run" 2>/dev/null || true
  kill -- -"$viewer" 2>/dev/null || true
  wait "$viewer" 2>/dev/null || true
}
compare()      { k compare assets/scenes/ms_vehicle_tab6.toml --contact kec,lookup2,lookup2-paper,online --duration 10 --save "$WORK/cmp.rrd"; shot compare "$WORK/cmp.rrd" 15; }
paper()        { k paper --duration 10 --save "$WORK/pa.rrd"; shot paper "$WORK/pa.rrd" 15; }
study()        { k study assets/studies/wheelset_speed_sweep.toml --out "$WORK/sweep"; shot study "$WORK/sweep/study.rrd" 15; }
# docs/studies.md's picture: the Cooperrider car's critical-speed study (13 cases of 10 s)
study_cooperrider() { k study assets/studies/cooperrider_critical_speed.toml --out "$WORK/coop"; shot study_cooperrider "$WORK/coop/study.rrd" 15; }
bench_precision() {
  k bench precision --duration 1.5 --contact kec,lookup --method bdf --rtol 1e-3,1e-4,1e-5 \
    --reference-contact kec --reference-rtol 1e-7 --save "$WORK/bp.rrd"
  shot bench_precision "$WORK/bp.rrd"
}

ALL=(profiles contact kec design_wheel creep patch track run run_safety run_curve live compare paper study study_cooperrider bench_precision)
for name in "${@:-${ALL[@]}}"; do
  "$name"
done
