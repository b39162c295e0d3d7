#!/usr/bin/env bash
# The product speaks of itself only. Fails (exit 1, one FILE:LINE: line per hit) when a text file
# of the repository (code, shaders, tests, docs, configs, scripts) speaks of how it was made
# instead of what it does:
#   - work sessions, helpers, agents, "the lead", milestones, milestone numbers M1..M16;
#   - dates of work (2026-12-02) and paths of a development machine (/work/..., ../shared/...).
# The words are matched whole and case-insensitively ("lead to" and "leading" are English, not
# a role); what is a real use anyway (Moreland's M1, a shell helper function) is listed with its
# file in scripts/check-words.allow. scripts/test.sh runs this before the build.
#   scripts/check-words.sh [PATH...]      default: every file git tracks or would track
set -euo pipefail
cd "$(dirname "$0")/.."
allow=scripts/check-words.allow

# label <TAB> Perl regular expression
rules=$(cat <<'EOF'
work session	(?i)\bsessions?\b
helper	(?i)\bhelpers?\b
agent	(?i)\bagents?\b
the lead	(?i)\blead\b(?!\s+(?:to|into|up|through)\b)
milestone	(?i)\bmilestones?\b
milestone number	\bM(?:[1-9]|1[0-6])\b
date of work	\b20\d\d-[01]\d-[0-3]\d\b
path of a development machine	(?:\.\./shared\b|(?<![\w}.$/-])/work/)
EOF
)

# Prints FILE:LINE: LABEL: TEXT for every hit in the given files (binary files skipped).
scan() {
  local label pattern
  while IFS=$'\t' read -r label pattern; do
    grep -nHIP -e "$pattern" -- "$@" 2>/dev/null | awk -v l="$label" '{
      i = index($0, ":"); j = index(substr($0, i + 1), ":")
      printf "%s: %s: %s\n", substr($0, 1, i + j - 1), l, substr($0, i + j + 1) }' || true
  done <<<"$rules"
}

# Drops the hits allow-listed as "FILE<TAB>TEXT" (TEXT a fixed part of the line).
filter_allowed() {
  awk -F'\t' -v allow="$1" '
    BEGIN { while ((getline line < allow) > 0) {
              if (line ~ /^#/ || line !~ /\t/) continue
              split(line, a, "\t"); file[++n] = a[1]; text[n] = a[2] } }
    { f = substr($0, 1, index($0, ":") - 1)
      for (k = 1; k <= n; k++) if (f == file[k] && index($0, text[k])) next
      print }'
}

# The rules must be able to fail: every line of `bad` is a hit, no line of `good` is.
self_test() {
  local d; d=$(mktemp -d)
  cat > "$d/bad" <<'EOF'
measured in session 7
the helper's branch
other agents building
for the lead: run this
(lead)
Milestone 3
done in M7
see M10 and M16
2026-12-02 measured
see ../shared/notes/x.md
the script in /work/bench/a.sh
EOF
  cat > "$d/good" <<'EOF'
which leads to a lower bound
this would lead to a crash
the leading dimension
a sessionless run
M17 and M0 and M1x
the M = max(a, b) rule
set(work ${CMAKE_CURRENT_BINARY_DIR}/work/x)
build/work/x
EOF
  local bad good nbad
  bad=$(scan "$d/bad" | cut -d: -f2 | sort -un | wc -l)
  nbad=$(wc -l < "$d/bad")
  good=$(scan "$d/good")
  rm -rf "$d"
  if [ "$bad" -ne "$nbad" ] || [ -n "$good" ]; then
    echo "check-words.sh: self-test failed: $bad of $nbad bad lines found; false hits: ${good:-none}" >&2
    exit 1
  fi
}

self_test
if [ $# -gt 0 ]; then
  files=("$@")
elif git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files --cached --others --exclude-standard | grep -vxF -e scripts/check-words.sh -e "$allow")
else
  mapfile -t files < <(find . -path ./build -prune -o -path ./.git -prune -o -type f -print | sed 's|^\./||' |
                       grep -vxF -e scripts/check-words.sh -e "$allow")
fi
existing=()
for f in "${files[@]}"; do [ -f "$f" ] && existing+=("$f"); done
[ ${#existing[@]} -gt 0 ] || exit 0
hits=$(scan "${existing[@]}" | filter_allowed "$allow" | sort -t: -k1,1 -k2,2n)
if [ -n "$hits" ]; then
  echo "$hits"
  echo "check-words.sh: $(wc -l <<<"$hits") lines speak of the work instead of the product (real uses: $allow)" >&2
  exit 1
fi
echo "check-words.sh: ok (${#existing[@]} files)"
