# depathd image: built on Debian 12, run on Debian 12 slim.
#
#   docker build -t depath .                  # or: podman build --format docker -t depath .
#   docker run --rm -p 50051:50051 -v depath-data:/var/lib/depath depath
#
# See deploy/README.md (compose with SQLite or PostgreSQL, Kubernetes, the registry-free
# image test).

# ---- builder: the same packages as scripts/setup.sh, then build and unit-test ----------
FROM debian:bookworm AS builder

# One package list for the setup script and this image (no second list here).
COPY scripts/packages.txt /tmp/packages.txt
RUN apt-get update \
 && grep -vE '^\s*(#|$)' /tmp/packages.txt \
    | DEBIAN_FRONTEND=noninteractive xargs apt-get install -y --no-install-recommends \
 && (command -v npm >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends npm) \
 && rm -rf /var/lib/apt/lists/*

WORKDIR /src
COPY . .
# The web view's npm packages as locked (the build bundles them into build/server/web).
RUN cd web && npm ci --no-audit --no-fund
# Parallel compile jobs; keep it small on shared machines.
ARG JOBS=2
RUN cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DDEPATH_BUILD_BENCH=OFF \
 && cmake --build build -j"${JOBS}"
# The image is only made from a build that passes its unit tests. CTEST_ARGS can narrow
# them (e.g. --build-arg CTEST_ARGS="-E slow"); the default runs them all.
ARG CTEST_ARGS=""
RUN ctest --test-dir build --output-on-failure -j"${JOBS}" ${CTEST_ARGS}
# Stripped binaries, and the packages that provide the libraries they link.
RUN install -D -s -m 0755 build/server/depathd /out/depathd \
 && install -D -s -m 0755 build/client/depath /out/depath \
 && cp -r build/server/web /out/web \
 && deploy/runtime-packages.sh /out/depathd /out/depath > /out/runtime-packages.txt \
 && cat /out/runtime-packages.txt

# ---- runtime: slim Debian, runtime libraries, both binaries, non-root ------------------
FROM debian:bookworm-slim

# tini as PID 1 forwards SIGTERM to depathd and reaps zombies, so a graceful stop works
# the same under docker, podman and Kubernetes without --init.
COPY --from=builder /out/runtime-packages.txt /tmp/runtime-packages.txt
RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive xargs -a /tmp/runtime-packages.txt \
    apt-get install -y --no-install-recommends tini \
 && rm -rf /var/lib/apt/lists/* /var/cache/apt/* /var/log/apt /var/log/dpkg.log \
           /tmp/runtime-packages.txt

COPY --from=builder /out/depathd /out/depath /usr/local/bin/
# The web view's bundled assets, in `web` beside depathd where it looks by default.
COPY --from=builder /out/web /usr/local/bin/web
# Fixed numeric ids so Kubernetes can verify runAsNonRoot; fail the build if any
# library is still missing rather than at container start.
RUN groupadd --gid 10001 depath \
 && useradd --uid 10001 --gid 10001 --no-create-home --home-dir /var/lib/depath \
            --shell /usr/sbin/nologin depath \
 && install -d -o depath -g depath -m 0750 /var/lib/depath \
 && ! ldd /usr/local/bin/depathd /usr/local/bin/depath | grep 'not found'

USER 10001:10001
WORKDIR /var/lib/depath
EXPOSE 50051
STOPSIGNAL SIGTERM
# Address the health check asks; change it together with --listen.
ENV DEPATH_HEALTH_ADDR=127.0.0.1:50051
HEALTHCHECK --interval=30s --timeout=5s --start-period=10s --retries=3 \
  CMD depath health --server "$DEPATH_HEALTH_ADDR"
ENTRYPOINT ["/usr/bin/tini", "--", "/usr/local/bin/depathd"]
# The job store is SQLite in /var/lib/depath (mount a volume there); env DEPATHD_STORE
# (e.g. postgresql://USER@HOST:PORT/DB, password in PGPASSWORD) takes precedence over it.
# Shutdown bound 8 s < docker stop's default 10 s, so a default stop is always clean (a
# running job checkpoints within it and resumes after the restart).
CMD ["--listen", "0.0.0.0:50051", "--data-dir", "/var/lib/depath", \
     "--shutdown-timeout-seconds", "8"]
