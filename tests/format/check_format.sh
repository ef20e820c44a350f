#!/usr/bin/env bash
# check_format.sh SOURCE_DIR: every C++ file of the tree is as clang-format (the tree's
# .clang-format) writes it; a file that is not is named, with the command that fixes it. C++
# sources have one extension, .cpp (headers .hpp; generated or foreign .h): a .cc is named too.
set -uo pipefail
src=$1
cd "$src" || exit 1
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.cc' '*.h')
else
  mapfile -t files < <(find common services tests bench examples -name '*.cpp' -o -name '*.hpp' \
    -o -name '*.cc' -o -name '*.h' | sort)
fi
((${#files[@]} > 100)) || { echo "FAIL: only ${#files[@]} C++ files found in $src"; exit 1; }
other=()
for f in "${files[@]}"; do [[ $f == *.cc ]] && other+=("$f"); done
if ((${#other[@]})); then
  echo "FAIL: C++ sources end in .cpp, not .cc: ${other[*]}"
  exit 1
fi
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "FAIL: ${#bad[@]} of ${#files[@]} files are not clang-formatted:"
  printf '  %s\n' "${bad[@]}"
  echo "fix: clang-format -i ${bad[*]}"
  exit 1
fi
echo "PASS: ${#files[@]} C++ files as clang-format writes them"
