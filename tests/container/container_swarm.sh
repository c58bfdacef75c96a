#!/usr/bin/env bash
# The container deployment, tested with podman (docs/deploy-containers.md):
#   container_swarm.sh image   SRC OUT [BUILD]          base image (made once) + the pheromesh image (layers reused);
#                                                       with BUILD, from BUILD's programs (build-image.sh --programs-from)
#   container_swarm.sh compose SRC OUT DOMAIN VENDORS   the compose swarm of small-test, to its end
#   container_swarm.sh kube    SRC OUT DOMAIN VENDORS   deploy/k8s/swarm.yaml through expand-statefulsets and
#                                                       `podman kube play`, to its end
# VENDORS: cyclone | fastdds | mixed (place agents Cyclone, UAVs Fast DDS, ground Cyclone).
# A swarm passes when its ground station exits 0 by itself (--until-done), every
# other process ends cleanly on the End it sends, and metrics.json shows every
# UAV and place agent finished, sent = applied + rejected + lost with none lost,
# coverage > 0 (check_metrics.py). Everything this script creates is named
# phmc-<mode>-<domain>... and removed at exit; the swarm's traffic stays on the
# bridge network it creates (plus the console's port published on 127.0.0.1).
# The figures it prints (seconds, sizes) go to OUT/times.txt.
set -euo pipefail
MODE=$1 SRC=$2 OUT=$3
DOMAIN=${4:-90} VENDORS=${5:-cyclone}
IMAGE=${PHEROMESH_IMAGE:-localhost/pheromesh:latest}
PODMAN="$SRC/scripts/podman.sh"
P() { "$PODMAN" "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
step() { echo "--- $(date +%T) $*"; }
now() { date +%s.%N; }
since() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$1" "$(now)"; }
record() { echo "$*" | tee -a "$OUT/times.txt"; }
UAVS=4 PLACES=4 # scenarios/small-test.textproto: 2 x 2 regions, 4 UAVs
SWARM_TIMEOUT=${SWARM_TIMEOUT:-300}

[ "$(id -u)" = 0 ] || { echo "SKIP: the container tests run podman as root"; exit 77; }
for tool in podman runc python3 nft; do
  command -v "$tool" > /dev/null || fail "$tool is not installed (scripts/install-deps.sh installs it)"
done
mkdir -p "$OUT"

case "$VENDORS" in
  cyclone | fastdds) DDS_PLACE=$VENDORS DDS_UAV=$VENDORS DDS_GROUND=$VENDORS ;;
  mixed) DDS_PLACE=cyclone DDS_UAV=fastdds DDS_GROUND=cyclone ;;
  *) fail "vendors '$VENDORS': cyclone, fastdds or mixed" ;;
esac
control_key() { od -An -tx1 -N32 /dev/urandom | tr -d ' \n'; }

# --- image ------------------------------------------------------------------
if [ "$MODE" = image ]; then
  command -v debootstrap > /dev/null || fail "debootstrap is not installed (scripts/install-deps.sh installs it)"
  rm -f "$OUT/times.txt"
  step "base image"
  t=$(now)
  "$SRC/scripts/container-base-image.sh"
  record "base image: $(since "$t") s"
  from=()
  if [ -n "${4:-}" ]; then
    from=(--programs-from "$4")
    step "pheromesh image $IMAGE from the programs of $4"
  else
    step "pheromesh image $IMAGE (layers reused when the sources did not change)"
  fi
  t=$(now)
  "$SRC/deploy/container/build-image.sh" "${from[@]}" "$IMAGE" > "$OUT/build.log" 2>&1 || {
    tail -n 40 "$OUT/build.log"
    fail "the image did not build (whole log: $OUT/build.log)"
  }
  record "image build: $(since "$t") s ($(grep -c '^--> Using cache' "$OUT/build.log") steps from the cache)"
  record "$(tail -n 1 "$OUT/build.log")"
  step "what the image holds"
  out=$(P run --rm "$IMAGE" bash -c 'ls /opt/pheromesh/bin /opt/pheromesh/lib/pheromesh; id -u; ls /opt/pheromesh/share/pheromesh/scenarios/small-test.textproto')
  for b in pheromesh pheromesh-uav pheromesh-place pheromesh-ground pheromesh-entrypoint libpheromesh_dds_cyclone.so \
           libpheromesh_dds_fastdds.so 10001 small-test.textproto; do
    grep -q "$b" <<< "$out" || fail "the image lacks $b: $out"
  done
  # Every shared library the programs and their DDS modules load is in the runtime image.
  missing=$(P run --rm "$IMAGE" bash -c 'ldd /opt/pheromesh/bin/pheromesh* /opt/pheromesh/lib/pheromesh/*.so 2>/dev/null | grep "not found" || true')
  [ -z "$missing" ] || fail "libraries missing in the image: $missing"
  P run --rm "$IMAGE" pheromesh validate small-test > /dev/null ||
    fail "pheromesh validate small-test (a shipped scenario by name) did not run in the image"
  exit 0
fi

P image exists "$IMAGE" || fail "no image $IMAGE: the label container's image test makes it (deploy/container/build-image.sh [--programs-from BUILD])"
KEY=$(control_key)
NAME=phmc-$MODE-$DOMAIN
rm -rf "$OUT/logs" "$OUT/metrics.json" "$OUT/times.txt"
mkdir -p "$OUT/logs"

save_logs() {  # CONTAINER...
  local c
  for c in "$@"; do P logs "$c" > "$OUT/logs/$c.log" 2>&1 || true; done
}

# Whether CONTAINER's log has PATTERN (read whole: `podman logs | grep -q`
# fails under pipefail when grep stops early).
log_has() {  # CONTAINER PATTERN
  P logs "$1" > "$OUT/logs/.probe" 2>&1 || true
  grep -q -- "$2" "$OUT/logs/.probe"
}

# Each process ran on the domain and over the vendor its role was given.
check_vendors() {  # PLACE_CONTAINER UAV_CONTAINER GROUND_CONTAINER
  save_logs "$@"
  grep -q "over $DDS_PLACE\b" "$OUT/logs/$1.log" || fail "$1 did not run over $DDS_PLACE"
  grep -q "over $DDS_UAV\b" "$OUT/logs/$2.log" || fail "$2 did not run over $DDS_UAV"
  grep -q "on domain $DOMAIN over $DDS_GROUND\b" "$OUT/logs/$3.log" || fail "$3 did not run on domain $DOMAIN over $DDS_GROUND"
}

# Waits for a container to exit; its exit code.
wait_exit() {  # CONTAINER TIMEOUT_S
  timeout "$2" "$PODMAN" wait "$1" 2> /dev/null | tail -n 1
}

# --- compose ----------------------------------------------------------------
if [ "$MODE" = compose ]; then
  command -v podman-compose > /dev/null || fail "podman-compose is not installed (scripts/install-deps.sh installs it)"
  PORT=$((18000 + DOMAIN))
  compose() {
    PHEROMESH_IMAGE=$IMAGE PHEROMESH_CONTROL_KEY=$KEY PHEROMESH_DOMAIN=$DOMAIN PHEROMESH_CONSOLE_PORT=$PORT \
      PHEROMESH_DDS_PLACE=$DDS_PLACE PHEROMESH_DDS_UAV=$DDS_UAV PHEROMESH_DDS_GROUND=$DDS_GROUND \
      podman-compose --podman-path "$PODMAN" -p "$NAME" -f "$SRC/deploy/compose/compose.yaml" "$@"
  }
  services=(place-0 place-1 place-2 place-3 uav-0 uav-1 uav-2 uav-3 ground)
  containers=("${services[@]/#/${NAME}_}")
  containers=("${containers[@]/%/_1}")
  cleanup() {
    save_logs "${containers[@]}"
    compose down -v > "$OUT/down.log" 2>&1 || true
    # podman-compose 1.0.3 leaves its network behind (-f: with any container still on it).
    if P network exists "${NAME}_swarm" 2> /dev/null; then P network rm -f "${NAME}_swarm" > /dev/null 2>&1 || true; fi
  }
  trap cleanup EXIT
  cleanup > /dev/null 2>&1 # a run killed before its cleanup

  step "podman-compose up: ${#services[@]} containers over $VENDORS (place $DDS_PLACE, uav $DDS_UAV, ground $DDS_GROUND), domain $DOMAIN"
  t=$(now)
  compose up -d > "$OUT/up.log" 2>&1 || { cat "$OUT/up.log"; fail "podman-compose up failed"; }
  # podman-compose 1.0.3 goes on when a container does not start: check each.
  for c in "${containers[@]}"; do
    P container exists "$c" || { cat "$OUT/up.log"; fail "podman-compose up did not make $c"; }
  done
  record "compose $VENDORS: up in $(since "$t") s"

  step "the console is published on 127.0.0.1:$PORT while the swarm flies"
  console=""
  for _ in $(seq 1 100); do
    if curl -sf "http://127.0.0.1:$PORT/api/info" -o "$OUT/info.json" 2> /dev/null; then console=up; break; fi
    [ "$(P inspect --format '{{.State.Running}}' "${NAME}_ground_1")" = true ] || break
    sleep 0.2
  done
  [ "$console" = up ] || fail "no console on 127.0.0.1:$PORT"

  step "the ground station ends the swarm (--until-done) and exits"
  rc=$(wait_exit "${NAME}_ground_1" "$SWARM_TIMEOUT") || fail "the ground station did not end within ${SWARM_TIMEOUT} s"
  record "compose $VENDORS: swarm ended $(since "$t") s after up"
  [ "$rc" = 0 ] || { save_logs "${NAME}_ground_1"; tail -n 20 "$OUT/logs/${NAME}_ground_1.log"; fail "the ground station exited with $rc"; }
  for c in "${containers[@]}"; do
    rc=$(wait_exit "$c" 60) || fail "$c still runs 60 s after the ground station ended the swarm"
    [ "$rc" = 0 ] || { save_logs "$c"; tail -n 20 "$OUT/logs/$c.log"; fail "$c exited with $rc"; }
  done

  check_vendors "${NAME}_place-1_1" "${NAME}_uav-2_1" "${NAME}_ground_1"

  step "metrics.json from the volume ${NAME}_out"
  volume_dir=$(P volume inspect --format '{{.Mountpoint}}' "${NAME}_out")
  cp "$volume_dir/metrics.json" "$OUT/metrics.json" || fail "no metrics.json in the volume ${NAME}_out"
  python3 "$SRC/tests/container/check_metrics.py" "$OUT/metrics.json" "$UAVS" "$PLACES"
  record "compose $VENDORS: total $(since "$t") s"
  exit 0
fi

# --- kube -------------------------------------------------------------------
[ "$MODE" = kube ] || fail "mode '$MODE': image, compose or kube"
PREFIX=$NAME-
NET=$NAME
SECRET=${PREFIX}pheromesh-control
NFT=phmc_kube_$DOMAIN
PLAY="$OUT/pods.yaml"
MON="$OUT/monitor.yaml"
MONITOR=${PREFIX}monitor-pod-0-monitor # podman names a Deployment's pod NAME-pod-0
pods=(place-0 place-1 place-2 place-3 uav-0 uav-1 uav-2 uav-3)
cleanup() {
  local c
  for c in "${pods[@]}"; do save_logs "$PREFIX$c-${c%-*}"; done
  save_logs "${PREFIX}ground-ground" "$MONITOR"
  if [ -f "$MON" ]; then P kube down "$MON" >> "$OUT/down.log" 2>&1 || true; fi
  if [ -f "$PLAY" ]; then P kube down "$PLAY" >> "$OUT/down.log" 2>&1 || true; fi
  # A run killed before its cleanup (its OUT may be another build's, with no
  # pods.yaml to kube down) left pods on the network, holding the volumes:
  # removed by name.
  local pod
  for pod in $(P pod ls --filter "name=^$PREFIX" --format '{{.Name}}' 2> /dev/null); do
    P pod rm -f "$pod" > /dev/null 2>&1 || true
  done
  local v
  for v in "${PREFIX}pheromesh-out" "${PREFIX}pheromesh-monitor-out"; do
    if P volume exists "$v" 2> /dev/null; then P volume rm "$v" > /dev/null || true; fi
  done
  if P secret inspect "$SECRET" > /dev/null 2>&1; then P secret rm "$SECRET" > /dev/null || true; fi
  if P network exists "$NET" 2> /dev/null; then P network rm -f "$NET" > /dev/null || true; fi
  nft delete table bridge "$NFT" > /dev/null 2>&1 || true
}
trap cleanup EXIT
cleanup > /dev/null 2>&1

# Cells by name: podman has no Service, so place-R.pheromesh-swarm and
# ground.pheromesh-swarm do not resolve; the pods' own names (PREFIX-place-R,
# PREFIX-ground), which podman's network DNS serves, stand in for them. Only
# these two names differ from the manifests.
NAMES=(--env "PHEROMESH_PLACE_NAME=${PREFIX}place-{region}" --env "PHEROMESH_GROUND_NAME=${PREFIX}ground")
step "expand-statefulsets deploy/k8s/swarm.yaml (prefix $PREFIX)"
"$SRC/deploy/k8s/expand-statefulsets" --prefix "$PREFIX" --image "$IMAGE" --env "PHEROMESH_DOMAIN=$DOMAIN" "${NAMES[@]}" \
  "$SRC/deploy/k8s/swarm.yaml" > "$PLAY" 2> "$OUT/expand.log" || { cat "$OUT/expand.log"; fail "expand-statefulsets failed"; }
[ "$(grep -c '^kind: Pod$' "$PLAY")" = 9 ] || fail "expected 9 pods in $PLAY"
grep -A1 'name: PHEROMESH_DDS_PROFILE$' "$PLAY" | grep -q 'value: cells$' || fail "deploy/k8s/swarm.yaml does not run in cells"
"$SRC/deploy/k8s/expand-statefulsets" --prefix "$PREFIX" --image "$IMAGE" --env "PHEROMESH_DOMAIN=$DOMAIN" "${NAMES[@]}" \
  --env "PHEROMESH_DDS=$DDS_GROUND" --configmaps-from "$SRC/deploy/k8s/swarm.yaml" "$SRC/deploy/k8s/monitor.yaml" > "$MON" 2>> "$OUT/expand.log" ||
  { cat "$OUT/expand.log"; fail "expand-statefulsets failed on monitor.yaml"; }
# Each role's vendor, set in its pods (the ConfigMap sets one for all).
python3 - "$PLAY" "$DDS_PLACE" "$DDS_UAV" "$DDS_GROUND" << 'PY'
import sys, yaml
path, place, uav, ground = sys.argv[1:]
docs = list(yaml.safe_load_all(open(path)))
for d in docs:
    if d.get("kind") != "Pod":
        continue
    vendor = {"place": place, "uav": uav, "ground": ground}[d["metadata"]["labels"]["app.kubernetes.io/component"]]
    for c in d["spec"]["containers"]:
        c["env"] = [e for e in c.get("env", []) if e["name"] != "PHEROMESH_DDS"] + [{"name": "PHEROMESH_DDS", "value": vendor}]
yaml.safe_dump_all(docs, open(path, "w"), sort_keys=False)
PY

step "the control key as a podman secret (a JSON map of key -> base64, what podman 4.3's secretKeyRef reads)"
printf '{"key":"%s"}' "$(printf %s "$KEY" | base64 -w0)" | P secret create "$SECRET" - > /dev/null
P network create "$NET" > /dev/null
# Pod networks rarely carry multicast: this one carries none. Every multicast
# frame between two pods on the network's bridge is counted and dropped, so
# the swarm must discover itself by unicast (cells, by the hubs' names).
subnet=$(P network inspect --format '{{range .Subnets}}{{.Subnet}} {{end}}' "$NET" | awk '{print $1}')
[ -n "$subnet" ] || fail "no subnet for the network $NET"
nft add table bridge "$NFT"
nft add chain bridge "$NFT" forward "{ type filter hook forward priority 0; policy accept; }"
nft add rule bridge "$NFT" forward ip saddr "$subnet" ip daddr 224.0.0.0/4 counter drop

step "podman kube play: 9 pods over $VENDORS, the headless Service as the alias pheromesh-swarm on $NET"
t=$(now)
P kube play --network "$NET:alias=pheromesh-swarm" "$PLAY" > "$OUT/play.log" 2>&1 || { cat "$OUT/play.log"; fail "podman kube play failed"; }
record "kube $VENDORS: played in $(since "$t") s"
step "podman kube play deploy/k8s/monitor.yaml (a Deployment, played by podman itself): a monitor that knows only the domain"
P kube play --network "$NET:alias=pheromesh-swarm" "$MON" > "$OUT/play-monitor.log" 2>&1 ||
  { cat "$OUT/play-monitor.log"; fail "podman kube play of the monitor failed"; }

step "every pod has the hostname the StatefulSet controller gives it"
for c in "${pods[@]}"; do
  h=$(P exec "$PREFIX$c-${c%-*}" cat /proc/sys/kernel/hostname 2> /dev/null || echo "?")
  [ "$h" = "$c" ] || fail "pod $PREFIX$c has the hostname '$h', not $c"
done

step "the ground station (Job) ends the swarm and exits"
rc=$(wait_exit "${PREFIX}ground-ground" "$SWARM_TIMEOUT") || fail "the ground station did not end within ${SWARM_TIMEOUT} s"
record "kube $VENDORS: swarm ended $(since "$t") s after play"
[ "$rc" = 0 ] || { save_logs "${PREFIX}ground-ground"; tail -n 20 "$OUT/logs/${PREFIX}ground-ground.log"; fail "the ground station exited with $rc"; }

step "every place agent and UAV ended cleanly and holds (PHEROMESH_AFTER_EXIT=hold: a StatefulSet restarts what exits)"
for c in "${pods[@]}"; do
  container="$PREFIX$c-${c%-*}"
  ok=""
  for _ in $(seq 1 60); do
    if log_has "$container" "finished; holding until stopped"; then ok=1; break; fi
    [ "$(P inspect --format '{{.State.Running}}' "$container")" = true ] || break
    sleep 1
  done
  [ -n "$ok" ] || { save_logs "$container"; tail -n 20 "$OUT/logs/$container.log"; fail "$container did not end cleanly"; }
  [ "$(P inspect --format '{{.RestartCount}}' "$container")" = 0 ] || fail "$container was restarted"
done

check_vendors "${PREFIX}place-1-place" "${PREFIX}uav-2-uav" "${PREFIX}ground-ground"

step "the monitor attached, saw the end and holds"
ok=""
for _ in $(seq 1 60); do
  if log_has "$MONITOR" "finished; holding until stopped"; then ok=1; break; fi
  [ "$(P inspect --format '{{.State.Running}}' "$MONITOR")" = true ] || break
  sleep 1
done
[ -n "$ok" ] || { save_logs "$MONITOR"; tail -n 20 "$OUT/logs/$MONITOR.log"; fail "the monitor did not end cleanly"; }
log_has "$MONITOR" "attached: the whole swarm is shown" || fail "the monitor never showed the whole swarm"
log_has "$MONITOR" "on domain $DOMAIN over $DDS_GROUND" || fail "the monitor did not look on domain $DOMAIN"

step "metrics.json from the claim ${PREFIX}pheromesh-out"
volume_dir=$(P volume inspect --format '{{.Mountpoint}}' "${PREFIX}pheromesh-out")
cp "$volume_dir/metrics.json" "$OUT/metrics.json" || fail "no metrics.json in the volume ${PREFIX}pheromesh-out"
python3 "$SRC/tests/container/check_metrics.py" "$OUT/metrics.json" "$UAVS" "$PLACES"
volume_dir=$(P volume inspect --format '{{.Mountpoint}}' "${PREFIX}pheromesh-monitor-out")
cp "$volume_dir/metrics.json" "$OUT/monitor-metrics.json" || fail "no metrics.json in the volume ${PREFIX}pheromesh-monitor-out"
python3 - "$OUT/metrics.json" "$OUT/monitor-metrics.json" << 'PY' || fail "the monitor's accounting differs from the ground station's"
import json, sys
g, m = (json.load(open(p)) for p in sys.argv[1:])
keys = ("deposits_sent", "deposits_applied", "deposits_rejected", "deposits_lost")
print("monitor:", {k: m.get(k) for k in keys})
sys.exit(0 if all(g[k] == m.get(k) for k in keys) else 1)
PY
dropped=$(nft list table bridge "$NFT" | grep -o 'packets [0-9]*' | awk '{print $2}')
record "kube $VENDORS: total $(since "$t") s; multicast frames dropped on the bridge: ${dropped:-?}"

step "guard: the bridge rule does catch a pod's multicast (one datagram from place-0)"
P exec "${PREFIX}place-0-place" bash -c 'echo guard > /dev/udp/239.255.0.1/7400' || fail "place-0 could not send"
after=$(nft list table bridge "$NFT" | grep -o 'packets [0-9]*' | awk '{print $2}')
[ "${after:-0}" -gt "${dropped:-0}" ] || fail "the multicast rule on the bridge did not see place-0's datagram: the no-multicast check proves nothing"
