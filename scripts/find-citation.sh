#!/usr/bin/env bash
# Lists the code, the tests and the docs behind one citation of the papers:
#
#   scripts/find-citation.sh Shao 2020 eq. 4        (or "Shao 2020 eq. (4)")
#   scripts/find-citation.sh Duan 2009 Fig. 6
#   scripts/find-citation.sh Liu 2022 Table 1
#
# A mention of an equation counts when it names it alone ("Shao 2020 eq. (4)")
# or inside a range or list of the prose form ("Shao 2020 eqs. (1)–(8)",
# "Ravankar 2016 eqs. (3), (4) and (27)–(33)"; docs/contributing.md).
# Prints file:line: text, grouped as code, tests and docs; exits 1 when the
# citation is found nowhere and 2 on a malformed query.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  cat >&2 <<'EOF'
usage: find-citation.sh AUTHOR YEAR KIND NUMBER
  AUTHOR YEAR: Shao 2020, Liu 2022, Duan 2009, Ravankar 2016 or Shostak 2024
  KIND NUMBER: eq. 4 (or "eq. (4)"), Table 1, Fig. 6 (or Fig. 10b), Algorithm 2, Sec. 4.2
example: find-citation.sh Shao 2020 eq. 4
EOF
  exit 2
}

query="$*"
[[ -n $query ]] || usage
# "Shao 2020 eq. (4)" -> author, year, kind, number.
if [[ ! $query =~ ^(Shao|Liu|Duan|Ravankar|Shostak)[[:space:]]+([0-9]{4})[[:space:]]+(eq\.?|Table|Fig\.?|Algorithm|Sec\.?)[[:space:]]+\(?([0-9]+[a-z]?(\.[0-9]+)*)\)?$ ]]; then
  echo "find-citation.sh: cannot read '$query' as a citation" >&2
  usage
fi
author=${BASH_REMATCH[1]} year=${BASH_REMATCH[2]} kind=${BASH_REMATCH[3]%.} number=${BASH_REMATCH[4]}
case "$author $year" in
  "Shao 2020" | "Liu 2022" | "Duan 2009" | "Ravankar 2016" | "Shostak 2024") ;;
  *) echo "find-citation.sh: no paper '$author $year' (the papers: Shao 2020, Liu 2022, Duan 2009, Ravankar 2016, Shostak 2024)" >&2; exit 2 ;;
esac
if [[ $kind == eq && ! $number =~ ^[0-9]+$ ]]; then
  echo "find-citation.sh: an equation number is a whole number, not '$number'" >&2
  exit 2
fi

cd "$root"
list() {
  # $@: directories and files; prints the text files among them (not build trees)
  find "$@" \( -name build -o -name 'build-*' -o -name .git -o -name node_modules \) -prune -o -type f \
    \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.proto' -o -name '*.textproto' -o -name '*.idl' \
    -o -name '*.md' -o -name '*.py' -o -name '*.sh' -o -name '*.ts' -o -name '*.js' \) -print 2>/dev/null | sort || true
}
code=$(list common agent placeagent groundstation cli launch sweep experiments bench fuzz examples idl web/src scenarios)
tests=$(list tests)
docs=$(list docs README.md)

found=0
search() {
  local title=$1 files=$2
  [[ -n $files ]] || return 0
  # shellcheck disable=SC2086
  out=$(AUTHOR="$author $year" KIND="$kind" NUMBER="$number" perl -CSO -Mutf8 -MEncode -ne '
    BEGIN {
      $a = $ENV{AUTHOR}; $k = $ENV{KIND}; $n = $ENV{NUMBER};
      $sep = ($k eq "eq" || $k eq "Fig" || $k eq "Sec") ? "\\." : "";
    }
    # Decoded leniently (a byte that is not UTF-8 becomes U+FFFD), as the
    # check does: the test data holds such files.
    $_ = Encode::decode("UTF-8", $_);
    my $hit = 0;
    if ($k eq "eq") {
      $hit = 1 if /\Q$a\E eq\. \(\Q$n\E\)/;
      # Ranges and lists of the prose form: "A Y eqs. (1)–(8), (10) and (12)".
      while (!$hit && /\Q$a\E eqs\. ((?:\(\d+\)(?:[–-]\(\d+\))?)(?:(?:, | and )\(\d+\)(?:[–-]\(\d+\))?)*)/g) {
        my $l = $1;
        while ($l =~ /\((\d+)\)(?:[–-]\((\d+)\))?/g) {
          my ($lo, $hi) = ($1, defined $2 ? $2 : $1);
          $hit = 1 if $n >= $lo && $n <= $hi;
        }
      }
    } else {
      $hit = 1 if /\Q$a\E \Q$k\E$sep \Q$n\E(?![0-9.]*[0-9])/;
    }
    # The prose form: one label, then a list ("A Y Sec. 5.1.1, eqs.
    # (12)–(15) and Algorithms 2 and 3"); each number belongs to the kind
    # named last before it.
    my $eqs = qr/\(\d+\)(?:[–-]\(\d+\))?/;
    my $and = qr/(?:, and |, | and )/;
    my $num = qr/\d+[a-z]?(?:\.\d+)*/;
    my $item = qr/(?:eqs?\. $eqs(?:$and$eqs)*|(?:Secs?\.|Algorithms?|Tables?|Figs?\.) $num(?:$and$num)*)/;
    while (!$hit && /\Q$a\E ($item(?:$and$item)*)/g) {
      my ($l, $cur) = ($1, "");
      while (!$hit && $l =~ /(eqs?\.|Secs?\.|Algorithms?|Tables?|Figs?\.)|\((\d+)\)(?:[–-]\((\d+)\))?|(\d+[a-z]?(?:\.\d+)*)/g) {
        if (defined $1) {
          ($cur = $1) =~ s/s?\.?$//;
          $cur = "eq" if $cur eq "eq" || $cur eq "eqs";
        } elsif (defined $2) {
          my ($lo, $hi) = ($2, defined $3 ? $3 : $2);
          $hit = 1 if $cur eq "eq" && $k eq "eq" && $n >= $lo && $n <= $hi;
        } elsif ($cur eq $k && $4 eq $n) {
          $hit = 1;
        }
      }
    }
    if ($hit) { chomp(my $t = $_); $t =~ s/^\s+//; $t = substr($t, 0, 200) . " …" if length($t) > 200; print "$ARGV:$.: $t\n"; }
    close ARGV if eof;
  ' $files)
  if [[ -n $out ]]; then
    found=1
    echo "== $title ($(wc -l <<<"$out") lines)"
    echo "$out"
  fi
}
search code "$code"
search tests "$tests"
search docs "$docs"
if [[ $found -eq 0 ]]; then
  echo "find-citation.sh: no mention of '$query' in code, tests or docs" >&2
  exit 1
fi
