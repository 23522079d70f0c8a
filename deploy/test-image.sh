#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the depathd image and smoke-tests it without a Docker engine or a registry.
#
#   deploy/test-image.sh              # base images + build + run + SIGTERM check
#   deploy/test-image.sh --base-only  # only make the local Debian 12 base images
#
# Steps: install the daemonless tools from Debian (idempotent); make debian:bookworm and
# debian:bookworm-slim locally with mmdebstrap (tarballs cached, so reruns are fast) and
# import them under the names the Dockerfile uses; build with podman (--pull=never, no
# registry); start the server with host networking; check health from inside (the image's
# HEALTHCHECK) and from the host; run a small job; stop with SIGTERM and check it exits 0.
# Prints image size, build time and SIGTERM-to-exit time. Needs root (rootful podman).
#
# Environment: DEPATH_IMAGE_CACHE (default /var/tmp/depath-images), DEPATH_IMAGE (tag,
# default localhost/depath:test), DEPATH_TEST_PORT (default 50071: not 50051, so a
# developer's own server on this host is left alone), DEPATH_BUILD_JOBS (default 2),
# DEPATH_CTEST_ARGS (extra ctest arguments for the unit tests in the build, e.g. "-E slow"),
# DEPATH_CLIENT (host client binary; default build/client/depath, else the image's own).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cache="${DEPATH_IMAGE_CACHE:-/var/tmp/depath-images}"
image="${DEPATH_IMAGE:-localhost/depath:test}"
port="${DEPATH_TEST_PORT:-50071}"
jobs="${DEPATH_BUILD_JOBS:-2}"
name="depath-test-$$"
base_only=0
[ "${1:-}" = "--base-only" ] && base_only=1

elapsed() { awk -v t0="$1" -v t1="$(date +%s.%N)" 'BEGIN { printf "%.2f", t1 - t0 }'; }
log() { printf '\n== %s\n' "$*"; }
die() { printf 'test-image: FAIL: %s\n' "$*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || die "run as root (rootful podman, apt-get, mmdebstrap)"

# --- tools -------------------------------------------------------------------------------
tools=(podman buildah runc catatonit mmdebstrap uidmap)
missing=()
for p in "${tools[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# A private containers.conf: podman's default crun fails on this kind of host (hybrid
# cgroup v1/v2) and its default rlimits exceed the host's hard limits. Nothing under /etc
# is edited, so the host's own podman setup is untouched.
mkdir -p "$cache"
cat > "$cache/containers.conf" <<'CONF'
[containers]
default_ulimits = ["nofile=20000:20000", "nproc=32768:32768"]
[engine]
runtime = "runc"
CONF
export CONTAINERS_CONF="$cache/containers.conf"

# --- base images -------------------------------------------------------------------------
# Same shape as the Docker Hub images: minbase (Essential + apt), merged /usr; the slim one
# also drops docs, man pages and locales with dpkg path excludes, which stay in the image's
# /etc/dpkg/dpkg.cfg.d so packages installed later are slimmed too.
slim_opts=(
  --dpkgopt='path-exclude=/usr/share/doc/*'
  --dpkgopt='path-include=/usr/share/doc/*/copyright'
  --dpkgopt='path-exclude=/usr/share/man/*'
  --dpkgopt='path-exclude=/usr/share/info/*'
  --dpkgopt='path-exclude=/usr/share/locale/*'
  --dpkgopt='path-exclude=/usr/share/lintian/*'
  --dpkgopt='path-exclude=/usr/share/groff/*'
)
make_base() { # TAG TARBALL [mmdebstrap options...]
  local tag="$1" tar="$2"; shift 2
  if podman image exists "$tag"; then
    echo "base image $tag present"
    return
  fi
  if [ ! -s "$tar" ]; then
    log "mmdebstrap $tag -> $tar"
    mmdebstrap --variant=minbase --format=tar \
      --hook-dir=/usr/share/mmdebstrap/hooks/merged-usr "$@" \
      bookworm "$tar.part" /etc/apt/sources.list.d/debian.sources
    mv "$tar.part" "$tar"
  fi
  podman import --change 'CMD ["bash"]' "$tar" "$tag" >/dev/null
  echo "imported $tag"
}
t0=$SECONDS
make_base debian:bookworm "$cache/bookworm.tar"
make_base debian:bookworm-slim "$cache/bookworm-slim.tar" "${slim_opts[@]}"
echo "base images ready in $((SECONDS - t0)) s"
[ "$base_only" -eq 1 ] && exit 0

# --- build -------------------------------------------------------------------------------
# --format docker keeps HEALTHCHECK and STOPSIGNAL (the OCI format drops HEALTHCHECK).
# DEPATH_NO_CACHE=1 measures a cold build; by default unchanged layers are reused.
cache_opt=()
[ "${DEPATH_NO_CACHE:-0}" = 1 ] && cache_opt=(--no-cache)
log "podman build $image (JOBS=$jobs${cache_opt:+, no cache})"
t0=$(date +%s.%N)
podman build --pull=never --format docker "${cache_opt[@]}" --build-arg JOBS="$jobs" \
  --build-arg CTEST_ARGS="${DEPATH_CTEST_ARGS:-}" \
  -t "$image" -f "$root/Dockerfile" "$root"
build_s=$(elapsed "$t0")
size_b=$(podman image inspect --format '{{.Size}}' "$image")

# --- run ---------------------------------------------------------------------------------
work="$(mktemp -d)"
cleanup() {
  [ -n "${bg_pid:-}" ] && kill "$bg_pid" 2>/dev/null
  podman rm -f "$name" >/dev/null 2>&1 || true
  podman volume rm -f "$name-data" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

# Host networking: the server listens on the host's loopback, as a local install would.
# A named volume starts as a copy of the image's /var/lib/depath, so it is owned by the
# image's non-root user, as with compose. No --init: the image's tini must do that job.
log "starting $name on 127.0.0.1:$port"
# Without systemd, podman cannot schedule the periodic health timer and says so on every
# start/stop; the check itself is run below with `podman healthcheck run`.
quiet_timer() { grep -v 'systemd connection' >&2 || true; }
podman run -d --name "$name" --network host \
  -e DEPATH_HEALTH_ADDR="127.0.0.1:$port" -v "$name-data:/var/lib/depath" \
  "$image" --listen "127.0.0.1:$port" --data-dir /var/lib/depath \
  --shutdown-timeout-seconds 8 --log-format json >/dev/null 2> >(quiet_timer)

# The image's own HEALTHCHECK (depath health inside the container) until it passes.
healthy=0
for _ in $(seq 60); do
  if podman healthcheck run "$name" >/dev/null 2>&1; then healthy=1; break; fi
  [ "$(podman inspect --format '{{.State.Running}}' "$name")" = true ] || break
  sleep 0.5
done
[ "$healthy" = 1 ] || { podman logs "$name" >&2; die "container never became healthy"; }
echo "HEALTHCHECK (depath health in the container): healthy"

# The client from the host: this checkout's build if there is one, else the image's own
# client in a second container on the host network (still a separate process and stack).
client=("${DEPATH_CLIENT:-$root/build/client/depath}")
mount_dir="$root/tests/data"
if [ ! -x "${client[0]}" ]; then
  chmod 0777 "$work"
  client=(podman run --rm --network host -v "$root/tests/data:/mesh:ro" -v "$work:$work"
          --entrypoint depath "$image")
  mount_dir=/mesh
fi
echo "client: ${client[*]}"
"${client[@]}" health --server "127.0.0.1:$port" || die "depath health from the host failed"
echo "depath health from the host: SERVING"

# A small job: the smallest bundled mesh, from vertex 0 to its last vertex.
mesh="${DEPATH_TEST_MESH:-}"
if [ -z "$mesh" ]; then
  # shellcheck disable=SC2012 # (bundled file names are plain)
  mesh="$(ls -S "$root"/tests/data/*.off "$root"/tests/data/*.obj 2>/dev/null | tail -n1)"
fi
[ -n "$mesh" ] || die "no .off/.obj mesh in tests/data"
case "$mesh" in
  *.off) nv=$(grep -v '^\s*#' "$mesh" | sed -n 2p | awk '{print $1}') ;;
  *.obj) nv=$(grep -c '^v ' "$mesh") ;;
esac
log "job: $(basename "$mesh") ($nv vertices), 0 -> $((nv - 1)), method fmm"
"${client[@]}" run "$mount_dir/$(basename "$mesh")" --server "127.0.0.1:$port" \
  --source 0 --target $((nv - 1)) --method fmm --out "$work/result.json" \
  || die "depath run against the container failed"
python3 - "$work/result.json" <<'PY' || die "bad result"
import json, math, sys
r = json.load(open(sys.argv[1]))
assert len(r["points"]) >= 2 and math.isfinite(r["energy"]) and r["energy"] > 0, r
print(f'result: {len(r["points"])} points, energy {r["energy"]:.6g}, method {r["method"]}')
PY

# --- SIGTERM -----------------------------------------------------------------------------
# Stop while a long DE job is running, so the measured time includes a real drain.
"${client[@]}" run "$mount_dir/$(basename "$mesh")" --server "127.0.0.1:$port" \
  --source 0 --target $((nv - 1)) --method de --population 32 --generations 100000 \
  --stall 100000 --out "$work/long.json" >/dev/null 2>&1 &
bg_pid=$!
sleep 2
log "podman stop (SIGTERM, SIGKILL only after 30 s)"
t0=$(date +%s.%N)
podman stop --time 30 "$name" >/dev/null 2> >(quiet_timer)
stop_s=$(elapsed "$t0")
code=$(podman inspect --format '{{.State.ExitCode}}' "$name")
podman logs --tail 5 "$name" 2>&1 | sed 's/^/  log: /'
[ "$code" = 0 ] || die "server exit code $code after SIGTERM (137 = killed)"
wait "$bg_pid" 2>/dev/null || true
bg_pid=""

log "summary"
printf 'image           %s\n' "$image"
printf 'image size      %s MB (%s bytes)\n' "$(awk "BEGIN { printf \"%.1f\", $size_b / 1e6 }")" "$size_b"
printf 'build time      %.0f s%s\n' "$build_s" "${cache_opt:+ (no cache)}"
printf 'SIGTERM to exit %.2f s (exit code %s)\n' "$stop_s" "$code"
echo "test-image: PASS"
