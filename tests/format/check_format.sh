#!/usr/bin/env bash
# Checks that C++ sources follow the repository's .clang-format (120 columns, 4-space indents):
# prints each file clang-format would change, with the first lines it would change, and exits 1.
#   tests/format/check_format.sh [FILE_OR_FOLDER...]   (default: every layer's sources and tests/)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
style="$root/.clang-format"
command -v clang-format > /dev/null || { echo "check_format: clang-format is not installed (bash scripts/setup.sh installs it)" >&2; exit 2; }
targets=("$@")
skip=(-false)  # the fixtures (files that fail on purpose) are checked only when named
if ((${#targets[@]} == 0)); then
  skip=(-path '*fixture*')
  for dir in "$root"/*/; do
    case "$(basename "$dir")" in build*|shaders|assets|docs|scripts|cmake) continue ;; esac
    targets+=("$dir")
  done
fi
bad=0
while IFS= read -r -d '' file; do
  if ! diff -q "$file" <(clang-format --style="file:$style" "$file") > /dev/null; then
    echo "${file#"$root"/} does not follow .clang-format (clang-format -i --style=file $file fixes it):"
    diff "$file" <(clang-format --style="file:$style" "$file") | head -6 | sed 's/^/    /' || true
    bad=1
  fi
done < <(find "${targets[@]}" \( -name '*.cpp' -o -name '*.h' \) -not \( "${skip[@]}" \) -print0 | sort -z)
exit $bad
