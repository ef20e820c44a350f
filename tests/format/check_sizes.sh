#!/usr/bin/env bash
# check_sizes.sh SOURCE_DIR: the C++ of common/ and services/ stays readable in pieces — no file
# over 500 lines, no function over 150 (issue 50's limits). Functions are found by Universal Ctags
# (their first and last lines); each one too long is named with its length.
set -uo pipefail
src=$1
max_file=${MAX_FILE_LINES:-500}
max_function=${MAX_FUNCTION_LINES:-150}
cd "$src" || exit 1
command -v ctags >/dev/null && ctags --version 2>/dev/null | grep -q "Universal Ctags" ||
  { echo "FAIL: Universal Ctags is missing (deploy/setup.sh installs universal-ctags)"; exit 1; }
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files 'common/*.cpp' 'common/*.hpp' 'services/*.cpp' 'services/*.hpp')
else
  mapfile -t files < <(find common services -name '*.cpp' -o -name '*.hpp' | sort)
fi
((${#files[@]} > 50)) || { echo "FAIL: only ${#files[@]} C++ files found in $src"; exit 1; }
status=0
long_files=$(wc -l "${files[@]}" | awk -v m="$max_file" '$2 != "total" && $1 > m {print "  " $2 ": " $1 " lines"}')
if [[ -n $long_files ]]; then
  echo "FAIL: files over $max_file lines:"
  echo "$long_files"
  status=1
fi
functions=$(ctags -x --_xformat="%{line} %{end} %F %N" --fields=+ne --kinds-c++=f --language-force=c++ \
  -o - "${files[@]}" 2>/dev/null)
counted=$(echo "$functions" | awk '$2 != "" {n++} END {print n + 0}')
((counted > 500)) || { echo "FAIL: ctags found only $counted functions"; exit 1; }
long_functions=$(echo "$functions" |
  awk -v m="$max_function" '$2 != "" && $2 - $1 + 1 > m {print "  " $3 ":" $1 " " $4 ": " $2 - $1 + 1 " lines"}')
if [[ -n $long_functions ]]; then
  echo "FAIL: functions over $max_function lines:"
  echo "$long_functions"
  status=1
fi
((status == 0)) && echo "PASS: ${#files[@]} files ≤ $max_file lines, $counted functions ≤ $max_function lines"
exit $status
