#!/usr/bin/env bash
# What the browser viewer costs the engine: `ldsm run --realtime` on a sequence without --serve,
# with --serve and no page, with a page on "another machine" (an HTTP client that reads the update
# stream, GET /stream, and draws nothing), and with the page open in headless Chromium on the
# same machine (its software WebGL competes for the same cores: the worst case). Prints the
# submit->tracked latency (mean, p50, p99), the tracking stage's p99 and the drops of each run.
# Usage: scripts/viewer-overhead.sh [DATASET] [BUILD_DIR]   (default ../shared/data/kitti00_200)
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=${1:-../shared/data/kitti00_200}
BUILD_DIR=${2:-build}
LDSM="$BUILD_DIR/apps/ldsm"
WORK=$(mktemp -d)
# The browser first (it still writes its profile into $WORK), then the scratch folder.
trap 'if [ -n "${BROWSER:-}" ]; then kill "$BROWSER" 2>/dev/null || true; wait "$BROWSER" || true; fi
      rm -rf "$WORK"' EXIT
PORT=${PORT:-18080}

report() {  # name stats.json
  python3 - "$1" "$2" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
lat = s["pipeline"]["latency"]["submit_to_tracked"]
track = s["stages"]["track"]
print(f"{sys.argv[1]:<22} submit->tracked mean {lat['mean_ms']:6.1f} p50 {lat['p50_ms']:6.1f} "
      f"p99 {lat['p99_ms']:6.1f} ms | track p99 {track['p99_ms']:6.1f} ms | "
      f"dropped {s['pipeline']['dropped_frames']} of {s['pipeline']['submitted_frames']}")
PY
}

"$LDSM" run --dataset "$DATA" --realtime --out "$WORK/plain" --no-eval >/dev/null 2>&1
report "no --serve" "$WORK/plain/stats.json"
"$LDSM" run --dataset "$DATA" --realtime --serve "127.0.0.1:$PORT" --out "$WORK/idle" \
  --no-eval >/dev/null 2>&1
report "--serve, no page" "$WORK/idle/stats.json"
# A page on another machine: an HTTP client that reads every update (GET /stream), draws nothing.
"$LDSM" run --dataset "$DATA" --realtime --serve "127.0.0.1:$PORT" --out "$WORK/remote" \
  --no-eval >/dev/null 2>&1 &
RUN=$!
python3 - "$PORT" >"$WORK/remote.log" 2>&1 <<'PY' &
import http.client, sys, time
port = int(sys.argv[1])
for _ in range(100):  # until the server is up
    try:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        conn.request("GET", "/stream")
        response = conn.getresponse()
        break
    except OSError:
        time.sleep(0.05)
# The stream's records (apps/viewer/wire_format.h): u32 length, then the message.
messages = received = 0
try:
    while True:
        head = response.read(4)
        if len(head) < 4: break
        n = int.from_bytes(head, "little")
        if len(response.read(n)) < n: break
        messages += 1; received += 4 + n
except (OSError, http.client.HTTPException):
    pass
print(f"remote page: {messages} messages, {received / 1e6:.1f} MB")
PY
wait  # the run, then the client (the server closes it)
report "--serve, remote page" "$WORK/remote/stats.json"
cat "$WORK/remote.log"
# A browser on the robot itself: headless Chromium, software WebGL on the same cores.
# The page connects while the run starts (it retries every 2 s until the server is up).
"$LDSM" --log-level info run --dataset "$DATA" --realtime --serve "127.0.0.1:$PORT" \
  --out "$WORK/page" --no-eval >/dev/null 2>"$WORK/page.log" &
RUN=$!
sleep 0.5
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=1280,800 \
  --user-data-dir="$WORK/profile" --remote-debugging-port=0 "http://127.0.0.1:$PORT/" \
  >/dev/null 2>&1 &
BROWSER=$!
wait "$RUN"
report "--serve, page open" "$WORK/page/stats.json"
grep -m1 -o "page connected.*" "$WORK/page.log" || echo "(the page never connected)"
