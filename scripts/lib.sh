# What the workspace scripts share; source it, do not run it.

log() { printf '\n== %s\n' "$*"; }
as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

# Installs those of the given Debian packages that are missing.
install_debian_packages() {
  local missing=()
  for package in "$@"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    log "installing Debian packages: ${missing[*]}"
    as_root apt-get update
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
  fi
}

# The catkin workspace of the repo $1: BULLET_SIM_WS, else the parent of a repo cloned as <ws>/src, else the
# repo itself (built in place).
workspace_of() {
  if [ -n "${BULLET_SIM_WS:-}" ]; then
    echo "$BULLET_SIM_WS"
  elif [ "$(basename "$1")" = src ]; then
    dirname "$1"
  else
    echo "$1"
  fi
}
