#!/usr/bin/env bash
# The citation check can fail: on a tree whose one bad mention sits in a file
# sorted after a file that is not UTF-8 (as tests/data/bad-utf8-name.textproto
# is), it must name that mention and exit 1; on the same tree with the mention
# written in the one form it must exit 0. Prose may name a range of
# equations, code may not. scripts/find-citation.sh finds an equation inside
# a prose range. Usage: check_citations_selftest.sh SRC
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scripts" "$tmp/tests/data" "$tmp/tests/unit"
touch "$tmp/README.md"
cp "$src/scripts/check-citations.sh" "$src/scripts/find-citation.sh" "$tmp/scripts/"
# Runs a script of $tmp/scripts with its arguments: its output in $out, its exit code in $rc.
try() {
  local script=$1
  shift
  set +e
  out=$(bash "$tmp/scripts/$script" "$@" 2>&1)
  rc=$?
  set -e
}
printf 'name: "caf\xe9 run"\n' > "$tmp/tests/data/a-latin1.textproto"
printf '// Fig. 6 of the paper\n' > "$tmp/tests/unit/z_test.cpp"
try check-citations.sh "$tmp"
if [[ $rc -ne 1 || $out != *"tests/unit/z_test.cpp:1: table/figure/algorithm without <Author> <Year>"* ]]; then
  echo "FAIL: expected exit 1 naming tests/unit/z_test.cpp:1, got exit $rc:"; echo "$out"; exit 1
fi
printf '// Shao 2020 Fig. 6 of the paper\n' > "$tmp/tests/unit/z_test.cpp"
try check-citations.sh "$tmp"
if [[ $rc -ne 0 ]]; then echo "FAIL: expected exit 0 on a clean tree, got $rc:"; echo "$out"; exit 1; fi

# A range in prose passes; the same range in a code comment does not.
mkdir -p "$tmp/docs"
printf 'the layers follow Shao 2020 eqs. (1)–(8) and Ravankar 2016 eqs. (3), (4) and (27)–(33).\n' > "$tmp/docs/a.md"
bash "$tmp/scripts/check-citations.sh" "$tmp" >/dev/null || { echo "FAIL: a range in prose was refused"; exit 1; }
printf '// Shao 2020 eqs. (1)–(8)\n' > "$tmp/tests/unit/y_test.cpp"
try check-citations.sh "$tmp"
if [[ $rc -ne 1 || $out != *"tests/unit/y_test.cpp:1:"* ]]; then
  echo "FAIL: expected a range in a code comment to be refused, got exit $rc:"; echo "$out"; exit 1
fi
printf '// Shao 2020 eq. (4): the obstacle layer\n' > "$tmp/tests/unit/y_test.cpp"

# The finder lists the single mention and the prose ranges that cover it.
out=$(bash "$tmp/scripts/find-citation.sh" Shao 2020 eq. 4)
for want in "tests/unit/y_test.cpp:1:" "docs/a.md:1:"; do
  [[ $out == *"$want"* ]] || { echo "FAIL: find-citation.sh Shao 2020 eq. 4 did not list $want:"; echo "$out"; exit 1; }
done
out=$(bash "$tmp/scripts/find-citation.sh" Ravankar 2016 "eq. (30)")
[[ $out == *"docs/a.md:1:"* ]] || { echo "FAIL: eq. (30) inside (27)–(33) not found:"; echo "$out"; exit 1; }
for q in "Shao 2020 eq. 9" "Ravankar 2016 eq. 26"; do
  # shellcheck disable=SC2086
  try find-citation.sh $q
  [[ $rc -eq 1 ]] || { echo "FAIL: find-citation.sh $q should find nothing (exit 1), got $rc"; exit 1; }
done
# One label, then a list of sections, equations, algorithms and figures:
# passes in prose, and the finder finds each item (and no prefix of one).
printf 'Shao 2020 Sec. 5.1.2, eqs. (17)–(24) and Algorithms 3 and 4; Shao 2020 Figs. 9 and 10b.\n' > "$tmp/docs/b.md"
bash "$tmp/scripts/check-citations.sh" "$tmp" >/dev/null || { echo "FAIL: a labelled list in prose was refused"; exit 1; }
for q in "Shao 2020 Sec. 5.1.2" "Shao 2020 eq. 20" "Shao 2020 Algorithm 4" "Shao 2020 Fig. 10b"; do
  # shellcheck disable=SC2086
  out=$(bash "$tmp/scripts/find-citation.sh" $q)
  [[ $out == *"docs/b.md:1:"* ]] || { echo "FAIL: $q inside a labelled list not found:"; echo "$out"; exit 1; }
done
for q in "Shao 2020 Sec. 5.1" "Shao 2020 Fig. 10" "Shao 2020 Algorithm 2"; do
  # shellcheck disable=SC2086
  try find-citation.sh $q
  [[ $out != *"docs/b.md"* ]] || { echo "FAIL: $q matched docs/b.md:"; echo "$out"; exit 1; }
done
# A list item after a break in the list needs its label again.
printf 'Shao 2020 Sec. 5.1.1 (the leader), Sec. 5.1.2\n' > "$tmp/docs/b.md"
try check-citations.sh "$tmp"
if [[ $rc -ne 1 || $out != *"docs/b.md:1: section not as"* ]]; then
  echo "FAIL: an unlabelled section after a break was not refused, got exit $rc:"; echo "$out"; exit 1
fi
rm "$tmp/docs/b.md"
try find-citation.sh Smith 2020 eq. 1
[[ $rc -eq 2 ]] || { echo "FAIL: an unknown paper should exit 2, got $rc"; exit 1; }
echo "the check names a bad mention after a non-UTF-8 file, passes a clean tree, prose ranges and labelled lists, refuses ranges in code and unlabelled items after a break; the finder finds mentions inside ranges and lists"
