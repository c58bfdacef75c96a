#!/usr/bin/env bash
# Checks that every citation of the papers in comments and docs has one form:
#   Shao 2020 eq. (9)   Shao 2020 Table 1   Duan 2009 Fig. 5
#   Liu 2022 Algorithm 1   Shao 2020 Sec. 4.2
# Code, scenario and IDL comments: one equation (table, figure, ...) per
# mention, so that grep finds every piece of code behind an equation. Prose
# (*.md) may also name, after one label, a list of what it cites:
#   Shao 2020 eqs. (1)–(8)   Ravankar 2016 eqs. (3), (4) and (27)–(33)
#   Shao 2020 Sec. 5.1.1, eqs. (12)–(15) and Algorithms 2 and 3
# (scripts/find-citation.sh finds a mention inside such a range). See
# docs/contributing.md. Usage: check-citations.sh [repo root].
# Prints file:line: text for each bad mention and exits 1 if there is one.
# C++ and textproto string literals are not checked (they are code).
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"

files=$(
  {
    find common agent placeagent groundstation cli launch sweep experiments bench tests \
      \( -name build -o -name 'build-*' -o -name .git -o -name node_modules \) -prune -o \
      -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.proto' -o -name '*.textproto' \) -print
    # docs/contributing.md shows the bad forms on purpose.
    find docs -type f -name '*.md' ! -path docs/contributing.md
    find scenarios -type f -name '*.textproto'
    find idl -type f -name '*.idl'
    echo README.md
  } 2>/dev/null | sort
)

# shellcheck disable=SC2086
# Lines are decoded leniently (a byte that is not UTF-8 becomes U+FFFD, as in
# the test data of bad scenarios), so no file stops the check half-way; an
# error of perl itself still fails it ($? is kept in END).
perl -CSO -Mutf8 -MEncode -ne '
  BEGIN { $bad = 0; $cite = qr/(?:Shao 2020|Liu 2022|Duan 2009|Ravankar 2016|Shostak 2024)/; }
  $_ = Encode::decode("UTF-8", $_);
  my $t = $_;
  # Code files: drop string literals, keep comments and code.
  $t =~ s/"(?:\\.|[^"\\])*"//g if $ARGV !~ /\.md$/;
  my @why;
  my $prose = $ARGV =~ /\.md$/;
  # Prose: one label, then a list of what it cites, in the one form:
  # "Shao 2020 Sec. 5.1.1, eqs. (12)–(15) and Algorithms 2 and 3".
  my $eqs = qr/\(\d+\)(?:[–-]\(\d+\))?/;
  my $and = qr/(?:, and |, | and )/;
  my $num = qr/\d+[a-z]?(?:\.\d+)*/;
  my $item = qr/(?:eqs?\. $eqs(?:$and$eqs)*|(?:Secs?\.|Algorithms?|Tables?|Figs?\.) $num(?:$and$num)*)/;
  $t =~ s/$cite $item(?:$and$item)*//g if $prose;
  push @why, "range or list after eq."
    if $t =~ /eq\. \(\d+\)\s*(?:[-–—]|to\b|,|and\b|or\b)\s*\(\d+\)/
      || $t =~ /eq\. \(\d+\)\s*(?:[-–—]|to\b|,|and\b|or\b)\s*\d/;
  push @why, "et al. before a year" if $t =~ /\bet al\.?,?\s*\(?(?:19|20)\d\d/;
  push @why, "\"Eq\"/\"eqs\"/\"equation\"" if $t =~ /\b(?:Eqs?|EQS?|eqs|[Ee]quations?)\b\.?\s*\(?\d/;
  (my $u = $t) =~ s/$cite (?:eq\. \(\d+\)|Table \d+|Fig\. \d+[a-z]?|Algorithm \d+|Sec\. \d+(?:\.\d+)*)//g;
  push @why, "eq. without <Author> <Year> or not as eq. (N)" if $u =~ /\beq\b\.?\s*\(?\d/;
  push @why, "table/figure/algorithm without <Author> <Year>"
    if $u =~ /\b(?:Tables?\s+\d|Tabs?\.\s*\d|Figs?\.\s*\d|Figures?\s+\d|Algorithms?\s+\d|Alg\.\s*\d)/;
  push @why, "section not as <Author> <Year> Sec. N" if $u =~ /§|\b(?:Secs?\.|Sections?|sections?)\s*\d/;
  if (@why) { chomp(my $l = $_); $l =~ s/^\s+//; print "$ARGV:$.: $why[0]: $l\n"; $bad = 1; }
  close ARGV if eof;
  END { $? ||= $bad; }
' $files
