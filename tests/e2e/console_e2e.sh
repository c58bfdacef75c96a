#!/usr/bin/env bash
# End-to-end test of the web console with real processes and a real browser:
#   1. `pheromesh run --http` starts a small swarm (DDS vendor $DDS) and the console;
#   2. a command without the token is refused (401);
#   3. /metrics passes `promtool check metrics`;
#   4. pause holds the swarm's tick, resume releases it;
#   5. Debian's chromium, driven by playwright-core (web/e2e/console_live.mjs):
#      heat map drawn, UAV count, kill a UAV -> dead, pop-up obstacle ->
#      obstacle layer changes, screenshot;
#   6. restart the killed UAV through the console -> alive again;
#   7. after the run, `pheromesh replay` of the recording shows the same final
#      state as the live console (web/e2e/console_replay.mjs), screenshot.
# usage: console_e2e.sh BUILD_DIR SOURCE_DIR OUT_DIR DDS PORT DOMAIN
set -euo pipefail
BUILD=$1 SRC=$2 OUT=$3 DDS=$4 PORT=$5 DOMAIN=$6
BIN=$BUILD/bin
E2E=$BUILD/web/e2e
RUN=$OUT/run
REPLAY_PORT=$((PORT + 1))
fail() { echo "FAIL: $*" >&2; exit 1; }
step() { echo "--- $*"; }
for tool in chromium node promtool curl; do
  command -v "$tool" > /dev/null || fail "$tool is not installed (scripts/install-deps.sh installs it)"
done
node -e 'process.exit(Number(process.versions.node.split(".")[0]) >= 20 ? 0 : 1)' ||
  fail "playwright-core needs Node.js >= 20; this is $(node --version)"
[ -f "$E2E/console_live.mjs" ] || fail "$E2E/console_live.mjs missing: build the target pheromesh_web_assets"
rm -rf "$OUT"
mkdir -p "$OUT"
json() { node -e "let s='';process.stdin.on('data',d=>s+=d).on('end',()=>{const j=JSON.parse(s);console.log($1)})"; }

LPID= RPID=
cleanup() {
  [ -n "$LPID" ] && kill "$LPID" 2> /dev/null || true
  [ -n "$RPID" ] && kill "$RPID" 2> /dev/null || true
  wait 2> /dev/null || true
}
trap cleanup EXIT

step "start the swarm with the console on port $PORT over $DDS"
"$BIN/pheromesh" run "$SRC/scenarios/small-test.textproto" --uavs 4 --rate 10 --duration 60 --dds "$DDS" \
  --domain "$DOMAIN" --http "$PORT" --out "$RUN" > "$OUT/launcher.log" 2>&1 &
LPID=$!
URL=
for _ in $(seq 1 150); do
  URL=$(grep -o "http://127.0.0.1:$PORT/?token=[0-9a-f]*" "$OUT/launcher.log" | head -1 || true)
  if [ -n "$URL" ] && curl -sf "http://127.0.0.1:$PORT/api/info" > /dev/null; then break; fi
  kill -0 "$LPID" 2> /dev/null || { cat "$OUT/launcher.log"; fail "the launcher exited early"; }
  sleep 0.2
done
curl -sf "http://127.0.0.1:$PORT/api/info" > "$OUT/info.json" || fail "no console on port $PORT"
TOKEN=${URL##*token=}
API="http://127.0.0.1:$PORT/api"
command_as() {  # TOKEN BODY -> "CODE BODY"
  curl -s -o "$OUT/answer.json" -w '%{http_code}' -X POST -H "Authorization: Bearer $1" -d "$2" "$API/command"
}

step "commands need the token"
code=$(command_as wrong-token '{"kind":"pause"}')
[ "$code" = 401 ] || fail "a command with a wrong token answered $code, not 401"
code=$(command_as "$TOKEN" '{"kind":"fly-to-the-moon"}')
[ "$code" = 400 ] || fail "an unknown command answered $code, not 400"

step "wait until every UAV flies and every place agent reports"
for _ in $(seq 1 150); do
  alive=$(curl -sf "$API/frame" |
    json 'j.uavs.filter(u=>u.liveness==="alive").length + "/" + j.regions.filter(r=>r.liveness==="alive").length')
  [ "$alive" = 4/4 ] && break
  sleep 0.2
done
[ "$alive" = 4/4 ] || fail "alive UAVs / place agents in the console: $alive, not 4/4"

step "Prometheus exposition"
curl -sf "http://127.0.0.1:$PORT/metrics" > "$OUT/metrics.txt"
promtool check metrics < "$OUT/metrics.txt" || fail "promtool rejected /metrics (see $OUT/metrics.txt)"
grep -q '^pheromesh_uavs{state="alive"} 4$' "$OUT/metrics.txt" || fail "/metrics does not count 4 alive UAVs"
grep -q '^pheromesh_region_up{region="0"} 1$' "$OUT/metrics.txt" || fail "/metrics does not show region 0 up"

step "pause holds the tick, resume releases it"
code=$(command_as "$TOKEN" '{"kind":"pause"}')
[ "$code" = 200 ] || fail "pause answered $code: $(cat "$OUT/answer.json")"
sleep 1.5  # commands in flight settle
t1=$(curl -sf "$API/frame" | json 'j.tick')
sleep 2
t2=$(curl -sf "$API/frame" | json 'j.tick')
paused=$(curl -sf "$API/frame" | json 'j.paused')
[ "$paused" = true ] || fail "the console does not show the swarm paused"
[ "$t1" = "$t2" ] || fail "the tick went on while paused ($t1 -> $t2)"
code=$(command_as "$TOKEN" '{"kind":"resume"}')
[ "$code" = 200 ] || fail "resume answered $code"
sleep 2
t3=$(curl -sf "$API/frame" | json 'j.tick')
[ "$t3" -gt "$t2" ] || fail "the tick did not go on after resume ($t2 -> $t3)"
echo "paused at tick $t1..$t2 for 2 s; tick $t3 two seconds after resume"

step "browser: heat map, UAV count, kill, pop-up obstacle"
node "$E2E/console_live.mjs" --url "$URL" --uavs 4 --kill-uav 1 --lease-ms 1000 \
  --screenshot "$OUT/console-live.png" --timeout-s 30 | tee "$OUT/browser.json" || fail "browser checks failed"

step "restart the killed UAV through the console"
code=$(command_as "$TOKEN" '{"kind":"restart_uav","uav":1}')
[ "$code" = 200 ] || fail "restart answered $code: $(cat "$OUT/answer.json")"
for _ in $(seq 1 100); do
  l=$(curl -sf "$API/frame" | json 'j.uavs.find(u=>u.id===1).liveness')
  [ "$l" = alive ] && break
  sleep 0.2
done
[ "$l" = alive ] || fail "uav 1 is $l, not alive, 20 s after the restart"

step "wait for the end of the run"
wait "$LPID" || fail "pheromesh run failed: $(tail -5 "$OUT/launcher.log")"
LPID=
# Every UAV ends by itself, the restarted one too (before, it never heard a
# start it could admit and the launcher stopped it 150 s after the end).
! grep -q "still flying long after the expected end" "$OUT/launcher.log" ||
  fail "a UAV did not end by itself: $(grep -h 'finished at tick' "$RUN"/logs/uav-*.log)"
grep -q "uav 1 finished at tick [1-9]" "$RUN/logs/uav-1.log" || fail "the restarted uav 1 never flew: $(tail -3 "$RUN/logs/uav-1.log")"
grep -q "console command from http" "$RUN/logs/ground.log" 2> /dev/null || grep -q "console command from http" "$OUT/launcher.log" ||
  fail "the ground station did not log the commands"
[ -s "$RUN/console_final.json" ] || fail "no console_final.json"

step "replay the recording"
"$BIN/pheromesh" replay "$RUN/console.phrec" --http "$REPLAY_PORT" > "$OUT/replay.log" 2>&1 &
RPID=$!
for _ in $(seq 1 100); do curl -sf "http://127.0.0.1:$REPLAY_PORT/api/info" > /dev/null && break; sleep 0.1; done
node "$E2E/console_replay.mjs" --url "http://127.0.0.1:$REPLAY_PORT/" --expect-json "$RUN/console_final.json" \
  --screenshot "$OUT/console-replay.png" || fail "the replay differs from the live console"
code=$(curl -s -o /dev/null -w '%{http_code}' -X POST -d '{"kind":"pause"}' "http://127.0.0.1:$REPLAY_PORT/api/command")
[ "$code" = 401 ] || [ "$code" = 503 ] || fail "a replay accepted a command ($code)"
echo "PASS: screenshots in $OUT"
