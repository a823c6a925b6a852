# Sourced by scripts/compare_builds.sh and scripts/compare_rhs.sh (from the repository root):
# `compare_worktree REV` sets sha, short (its first 10 digits), root (this checkout) and tree, a
# detached git worktree of REV under target/compare/, made on first use. The older builds share
# the target directory target/compare/target.
compare_worktree() {
  sha="$(git rev-parse --verify "$1^{commit}")"
  short="${sha:0:10}"
  root="$PWD"
  tree="$root/target/compare/$short"
  if [ ! -d "$tree" ]; then
    git worktree add --detach --force "$tree" "$sha" >/dev/null
  fi
}
