# Sourced by the build scripts: use ccache when it is installed (scripts/packages.txt lists it),
# with paths taken relative to the checkout, so clones and worktrees in other folders (CI's
# fresh clone, a developer's worktree) hit the same cache entries.
depath_cache_flags=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
  export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-5G}"
  depath_cache_flags=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
