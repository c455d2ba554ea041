#!/usr/bin/env bash
# The documentation site (mkdocs.yml, docs/), after the workspace is built:
#
#   scripts/docs.sh           writes the generated pages (the plugin reference from the plugins' README.md and
#                             tag tables, each tool page's options from its --help, a page per launch file from
#                             its <arg>s, their nav entries)
#                             and builds the site into site/ with `mkdocs build --strict`
#   scripts/docs.sh --check   the same into a scratch copy, failing when a committed page differs from what the
#                             code generates (a stale page), when the build warns, when a page is not in the nav,
#                             or when an #anchor link lands on no heading (scripts/workspace.sh test runs it)
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib.sh
source "$REPO/scripts/lib.sh"
WS=$(workspace_of "$REPO")
export PATH=/usr/bin:$PATH:/usr/local/bin
set +u  # catkin's setup.bash reads unset variables
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u

generate() {  # $1: a folder holding mkdocs.yml and docs/
  local plugins=$1/docs/reference/plugins
  rm -f "$plugins"/*.md "$1"/docs/reference/launch/*.md  # what is gone loses its page
  "$WS/devel/lib/bullet_sim/plugin_reference" "$REPO/bullet_sim/plugins" "$plugins"
  /usr/bin/python3 "$REPO/scripts/docs_generate.py" "$1"
}

if [[ ${1:-} != --check ]]; then
  generate "$REPO"
  mkdocs build --strict --quiet --config-file "$REPO/mkdocs.yml"
  /usr/bin/python3 "$REPO/scripts/docs_check.py" "$REPO" "$REPO/site"
  exit 0
fi

SCRATCH=$(mktemp -d)
trap 'rm -rf "$SCRATCH"' EXIT
cp -r "$REPO/mkdocs.yml" "$REPO/docs" "$REPO/README.md" "$SCRATCH/"
generate "$SCRATCH"
status=0
if ! diff -ru "$REPO/docs" "$SCRATCH/docs" || ! diff -u "$REPO/mkdocs.yml" "$SCRATCH/mkdocs.yml"; then
  echo "FAILED: the committed pages above are stale: run scripts/docs.sh and commit what it writes" >&2
  status=1
fi
mkdocs build --strict --quiet --config-file "$SCRATCH/mkdocs.yml" --site-dir "$SCRATCH/site" || status=1
/usr/bin/python3 "$REPO/scripts/docs_check.py" "$SCRATCH" "$SCRATCH/site" || status=1
exit "$status"
