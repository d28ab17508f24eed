# Sourced by the study drivers: sets $aquaform to the aquaform binary: AQUAFORM_BIN, else the one
# on PATH, else the source tree's build/aquaform. The path is made absolute (jobs run elsewhere).
aquaform_find_bin() {
  local root=$1 bin=""
  if [ -n "${AQUAFORM_BIN:-}" ]; then
    bin=$AQUAFORM_BIN
  elif command -v aquaform > /dev/null 2>&1; then
    bin=$(command -v aquaform)
  elif [ -x "$root/build/aquaform" ]; then
    bin=$root/build/aquaform
  fi
  if [ -z "$bin" ] || [ ! -x "$bin" ]; then
    echo "no aquaform binary: set AQUAFORM_BIN, put aquaform on PATH, or build it (scripts/setup.sh builds build/aquaform)" >&2
    return 1
  fi
  aquaform=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
}
