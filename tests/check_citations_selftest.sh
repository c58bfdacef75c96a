#!/usr/bin/env bash
# The citation check can fail: on a tree whose one bad mention sits in a file
# sorted after a file that is not UTF-8 (as tests/data/bad-utf8-name.textproto
# is), it must name that mention and exit 1; on the same tree with the mention
# written in the one form it must exit 0. Usage: check_citations_selftest.sh SRC
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scripts" "$tmp/tests/data" "$tmp/tests/unit"
touch "$tmp/README.md"
cp "$src/scripts/check-citations.sh" "$tmp/scripts/"
printf 'name: "caf\xe9 run"\n' > "$tmp/tests/data/a-latin1.textproto"
printf '// Fig. 6 of the paper\n' > "$tmp/tests/unit/z_test.cpp"
set +e
out=$(bash "$tmp/scripts/check-citations.sh" "$tmp" 2>&1)
rc=$?
set -e
if [[ $rc -ne 1 || $out != *"tests/unit/z_test.cpp:1: table/figure/algorithm without <Author> <Year>"* ]]; then
  echo "FAIL: expected exit 1 naming tests/unit/z_test.cpp:1, got exit $rc:"; echo "$out"; exit 1
fi
printf '// Shao 2020 Fig. 6 of the paper\n' > "$tmp/tests/unit/z_test.cpp"
set +e
out=$(bash "$tmp/scripts/check-citations.sh" "$tmp" 2>&1)
rc=$?
set -e
if [[ $rc -ne 0 ]]; then echo "FAIL: expected exit 0 on a clean tree, got $rc:"; echo "$out"; exit 1; fi
echo "the check names a bad mention after a non-UTF-8 file, and passes a clean tree"
