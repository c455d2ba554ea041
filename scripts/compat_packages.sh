#!/usr/bin/env bash
# Opts the compatibility packages under compat/ in or out. Each carries a committed CATKIN_IGNORE, so a plain
# catkin_make never builds it. This removes that file where rospack finds no real package of the same name
# outside this repo and workspace (Debian 12 has none of them), and puts it back where one appears, so that our
# stand-in never shadows the real package.
#
#   scripts/compat_packages.sh [COMPAT_DIR [WORKSPACE]]    (defaults: the repo's compat/ and the repo)
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
COMPAT=$(cd "${1:-$REPO/compat}" && pwd)
WS=${2:-$REPO}

# Where rospack finds package $1, searching without this repo, its workspace and the compat folder; empty if
# nowhere.
real_package() {
  local path="" entry kept=()
  IFS=: read -r -a entries <<< "${ROS_PACKAGE_PATH:-}"
  for entry in "${entries[@]}"; do
    case "$(realpath -m "$entry")/" in
      "$REPO"/* | "$(realpath -m "$WS")"/* | "$COMPAT"/*) ;;
      *) kept+=("$entry") ;;
    esac
  done
  path=$(IFS=:; ROS_PACKAGE_PATH="${kept[*]}" rospack find "$1" 2>/dev/null) || true
  case "$(realpath -m "${path:-/nonexistent}")/" in
    "$REPO"/* | "$COMPAT"/*) path="" ;;
  esac
  echo "$path"
}

for package_xml in "$COMPAT"/*/package.xml; do
  [ -e "$package_xml" ] || continue
  dir=$(dirname "$package_xml")
  name=$(sed -n 's:.*<name>\(.*\)</name>.*:\1:p' "$package_xml" | head -1)
  real=$(real_package "$name")
  if [ -n "$real" ]; then
    if [ ! -e "$dir/CATKIN_IGNORE" ]; then
      echo "compat: $name is installed at $real; not building ours"
      printf '%s\n' "Opt-in compatibility package: scripts/compat_packages.sh (run by scripts/workspace.sh) removes this file when" \
        "the system has no real package of this name, and puts it back when one appears." > "$dir/CATKIN_IGNORE"
    fi
  elif [ -e "$dir/CATKIN_IGNORE" ]; then
    echo "compat: the system has no $name; building ours ($dir)"
    rm "$dir/CATKIN_IGNORE"
  fi
done
