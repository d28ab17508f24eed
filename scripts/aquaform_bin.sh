# Sourced by the study drivers (scripts/study_parallel.sh, scripts/slurm/study_array.sh): their
# arguments, and the aquaform binary.

# study_driver_args NAME SPEC N [OUT] [-- EXTRA...]: sets $spec and $out (absolute), $n and the
# array $extra (passed on to parallel or sbatch, which check them). Bad input ends the caller with
# 2 and one line naming the fix; nothing is made (study_driver_out makes OUT).
study_driver_args() {
  local name=$1
  shift
  local usage="usage: $name SPEC N [OUT] [-- options passed on]"
  refuse() { echo "$name: $1" >&2; exit 2; }
  (($# >= 2)) || refuse "SPEC and N are needed; $usage"
  spec=$1 n=$2 out=""
  shift 2
  if (($#)) && [ "$1" != "--" ]; then out=$1; shift; fi
  if (($#)); then [ "$1" = "--" ] || refuse "unknown argument '$1' after OUT; $usage"; shift; fi
  extra=("$@")
  [[ "$spec" != -* ]] || refuse "unknown argument '$spec' where SPEC goes; $usage"
  [ -f "$spec" ] || refuse "no spec file $spec; give a study spec such as assets/studies/tiny.json"
  # Decimal, no leading zero (08 is not a bash number), at most 9999 shards.
  [[ "$n" =~ ^[1-9][0-9]{0,3}$ ]] || refuse "N must be a positive number of shards (1 to 9999, no leading zero), not '$n'"
  [ -n "$out" ] || out="study_$(basename "$spec" .json)"
  [[ "$out" != -* ]] || refuse "unknown argument '$out' where OUT goes; $usage"
  [ ! -e "$out" ] || [ -d "$out" ] || refuse "OUT $out is a file; give a folder"
  spec=$(cd "$(dirname "$spec")" && pwd)/$(basename "$spec")
}

# study_driver_out NAME: makes $out/logs (after every other check) and makes $out absolute;
# a folder that cannot be made or written is bad input (2).
study_driver_out() {
  mkdir -p "$out/logs" 2>/dev/null && touch "$out/logs/.probe" 2>/dev/null ||
    { echo "$1: OUT $out cannot be made or written; give a folder you can write" >&2; exit 2; }
  rm -f "$out/logs/.probe"
  out=$(cd "$out" && pwd)
}

# aquaform_find_bin ROOT: sets $aquaform to the aquaform binary: AQUAFORM_BIN, else the one on
# PATH, else the source tree's build/aquaform. The path is made absolute (jobs run elsewhere).
aquaform_find_bin() {
  local root=$1 bin=""
  if [ -n "${AQUAFORM_BIN:-}" ]; then
    bin=$AQUAFORM_BIN
  elif command -v aquaform > /dev/null 2>&1; then
    bin=$(command -v aquaform)
  elif [ -x "$root/build/aquaform" ]; then
    bin=$root/build/aquaform
  fi
  if [ -n "${AQUAFORM_BIN:-}" ] && [ ! -x "$bin" ]; then  # bad input: 2, as a bad argument
    echo "AQUAFORM_BIN=$AQUAFORM_BIN is not an executable file; point it at the aquaform binary" >&2
    return 2
  fi
  if [ -z "$bin" ]; then
    echo "no aquaform binary: set AQUAFORM_BIN, put aquaform on PATH, or build it (scripts/setup.sh builds build/aquaform)" >&2
    return 1
  fi
  aquaform=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
}
