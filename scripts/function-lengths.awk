# Prints "FILE:LINE LENGTH NAME" for every function definition longer than
# `limit` lines (awk -v limit=80 -f function-lengths.awk FILE...). Used by
# scripts/check-structure.sh.
#
# A heuristic for our clang-formatted C++, not a parser: a definition starts
# on a line that ends in `) {` (also `) const {`, `) override {`,
# `) -> T {`) and is not a control statement, a lambda or an assignment; its
# length counts the lines from that one to the line of its closing brace,
# both included. Braces inside string and character literals, raw strings
# and // or /* */ comments do not count. NAME is the identifier before the
# first `(` of the signature, which may begin lines above.
function strip(s,    out, i, c, q) {
  # Removes what cannot hold a real brace: literals and comments. Keeps the
  # state of a raw string or block comment that runs over lines.
  out = ""
  i = 1
  while (i <= length(s)) {
    if (in_raw) {
      q = index(substr(s, i), raw_end)
      if (q == 0) return out
      i += q - 1 + length(raw_end)
      in_raw = 0
      continue
    }
    if (in_block) {
      q = index(substr(s, i), "*/")
      if (q == 0) return out
      i += q + 1
      in_block = 0
      continue
    }
    c = substr(s, i, 1)
    if (c == "/" && substr(s, i + 1, 1) == "/") return out
    if (c == "/" && substr(s, i + 1, 1) == "*") { in_block = 1; i += 2; continue }
    if (c == "R" && substr(s, i + 1, 1) == "\"" && substr(s, i - 1, 1) !~ /[A-Za-z0-9_]/) {
      q = index(substr(s, i + 2), "(")
      raw_end = ")" substr(s, i + 2, q - 1) "\""
      in_raw = 1
      i += 2 + q
      continue
    }
    if (c == "\"" || c == "'") {
      i++
      while (i <= length(s) && substr(s, i, 1) != c) i += (substr(s, i, 1) == "\\") ? 2 : 1
      i++
      continue
    }
    out = out c
    i++
  }
  return out
}
function count(s, ch,    n) { n = gsub(ch, "", s); return n }
function name_of(first, last,    k, s, p, balance, m) {
  # The signature's first line: walk up while its parentheses are unopened.
  balance = 0
  for (k = last; k >= first; k--) {
    s = code[k]
    balance += count(s, "\\(") - count(s, "\\)")
    if (balance >= 0) break
  }
  if (k < first) k = first
  s = code[k]
  p = index(s, "(")
  if (p == 0) return "?"
  s = substr(s, 1, p - 1)
  if (match(s, /[A-Za-z_~][A-Za-z0-9_:~<>]*[ \t]*$/)) return substr(s, RSTART, RLENGTH)
  return "?"
}
FNR == 1 { depth = 0; start = 0; in_raw = 0; in_block = 0; delete code }
{
  raw_line = $0
  line = strip($0)
  code[FNR] = line
  if (start == 0) {
    if (line ~ /\)[ \t]*(const)?[ \t]*(noexcept)?[ \t]*(override|final)?[ \t]*(->[ \t]*[A-Za-z0-9_:<>, ]+)?[ \t]*\{[ \t]*$/ &&
        line ~ /^[ \t]*[A-Za-z_~]/ &&
        line !~ /^[ \t]*(if|for|while|switch|catch|do|else|return|namespace|struct|class|enum|union|extern)[^A-Za-z0-9_]/ &&
        line !~ /^[ \t]*\}/) {
      before = line
      sub(/\(.*/, "", before)
      if (before !~ /=/ && line !~ /\[[^\]]*\]\(/ && line !~ /\[[^\]]*\][ \t]*\{[ \t]*$/) {
        start = FNR
        fname = name_of((FNR > 30 ? FNR - 30 : 1), FNR)
        fdepth = depth
      }
    }
  }
  depth += count(line, "\\{") - count(line, "\\}")
  if (start && depth <= fdepth && FNR > start) {
    n = FNR - start + 1
    if (n > limit) printf "%s:%d %d %s\n", FILENAME, start, n, fname
    start = 0
  }
}
