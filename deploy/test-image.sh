#!/usr/bin/env bash
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
