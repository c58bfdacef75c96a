#!/usr/bin/env bash
# The function-length measure of scripts/check-structure.sh can fail: a
# function of 81 lines is named with its file, line and length; one of 80
# lines is not; braces inside strings, raw strings, character literals and
# comments do not end a function early, and a lambda or a control statement
# is not taken for a definition. Usage: check_function_lengths_selftest.sh SRC
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# Writes a function NAME to FILE whose definition is LINES lines long, its
# body made of BODY_LINE repeated.
write_function() {
  local file=$1 name=$2 lines=$3 body_line=$4
  {
    echo "int $name(int x) {"
    for ((k = 0; k < lines - 2; ++k)); do echo "$body_line"; done
    echo "}"
  } >>"$file"
}
measure() { awk -v limit=80 -f "$src/scripts/function-lengths.awk" "$@"; }

write_function "$tmp/long.cpp" too_long 81 "  x += 1;"
out=$(measure "$tmp/long.cpp")
if [[ $out != "$tmp/long.cpp:1 81 too_long" ]]; then echo "FAIL: 81 lines not reported: '$out'"; exit 1; fi

write_function "$tmp/short.cpp" just_fits 80 "  x += 1;"
out=$(measure "$tmp/short.cpp")
if [[ -n $out ]]; then echo "FAIL: an 80-line function was reported: '$out'"; exit 1; fi

# Closing braces in literals and comments must not end the function early.
write_function "$tmp/literals.cpp" with_literals 90 '  s += "}"; c = '"'}'"'; // }'
sed -i '3a\  const char* r = R"(}\n}\n)"; /* } */' "$tmp/literals.cpp"
out=$(measure "$tmp/literals.cpp")
if [[ $out != "$tmp/literals.cpp:1 93 with_literals" ]]; then echo "FAIL: literals miscounted: '$out'"; exit 1; fi

# A long lambda or if block inside a short-enough function is not a definition of its own;
# a long one in a long function does not hide the function.
{
  echo "namespace n {"
  echo "void Outer::run(int a,"
  echo "                int b) const {"
  echo "  auto f = [&](int y) {"
  for ((k = 0; k < 85; ++k)); do echo "    y += 1;"; done
  echo "  };"
  echo "}"
  echo "}  // namespace n"
} >"$tmp/nested.cpp"
out=$(measure "$tmp/nested.cpp")
if [[ $out != "$tmp/nested.cpp:3 89 Outer::run" ]]; then echo "FAIL: nested: '$out'"; exit 1; fi
echo "function-lengths selftest: ok"
