#!/usr/bin/env bash
# Formats the results of scripts/bench/paper_tables.sh (results.csv, one row per run) as Markdown
# tables in the layout of Groß & Gumhold 2020: Table 1 sorting time per data set, Table 2 frame
# times with columns A-F (far / far+culling / far+culling+AO, near / near+culling /
# near+culling+AO) for opaque and transparent rendering, Table 3 the k sweep. A separate step so
# that the formatting can be checked by hand on a small CSV without rendering anything:
#   scripts/bench/paper_tables_format.sh RESULTS.csv [META.txt] > tables.md
# results.csv columns:
#   set,segments,view,mode,k,culling,ao,frames,frame_ms,sort_ms,status
#   view: far|near; mode: opaque|kbuffer; k: 0 for opaque; culling, ao: 0|1;
#   frame_ms, sort_ms: medians over the frames after the first, "-" when not measured;
#   status: ok | fail (the render failed) | skipped (culling not available).
# META.txt lines ("key: value") are printed as a list under the title. Missing runs print "-",
# failed ones "fail", skipped ones "n/a".
set -euo pipefail
csv=$1
meta=${2:-}

echo "# Performance tables (Groß & Gumhold 2020, Tables 1-3) on this machine"
echo
if [ -n "$meta" ] && [ -f "$meta" ]; then
  sed 's/^/- /' "$meta"
  echo
fi

# mawk-compatible (Debian's default awk): no asort, no gensub.
awk -F, '
function cell(key,   s) {
  if (!(key in status)) return "-"
  s = status[key]
  if (s == "fail") return "fail"
  if (s == "skipped") return "n/a"
  return ms[key]
}
function ratio(a, b,   x, y) {  # a / b as "2.3x", when both are numbers
  x = cell(a); y = cell(b)
  if (x !~ /^[0-9.]+$/ || y !~ /^[0-9.]+$/ || y + 0 == 0) return "-"
  return sprintf("%.2fx", x / y)
}
function seg(s,   n) {  # 1234567 -> 1,234,567
  n = s ""
  while (n ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]($|,)/, ",&", n)
  return n
}
NR == 1 { next }
/^#/ || NF < 11 { next }
{
  key = $1 "|" $3 "|" $4 "|" $5 "|" $6 "|" $7
  status[key] = $11; ms[key] = $9; sortms[key] = $10
  if (!($1 in segments)) { order[++nsets] = $1; segments[$1] = $2 }
  if ($2 != "-" && $2 + 0 > 0) segments[$1] = $2
}
END {
  print "## Table 1: sorting time per data set"
  print ""
  print "GPU radix sort of the per-segment depth keys (`sort` stage, ms, median), k-buffer k = 4 without culling."
  print ""
  print "| data set | segments | sort, far (ms) | sort, near (ms) |"
  print "|---|---:|---:|---:|"
  for (i = 1; i <= nsets; i++) {
    s = order[i]
    f = s "|far|kbuffer|4|0|0"; n = s "|near|kbuffer|4|0|0"
    printf "| %s | %s | %s | %s |\n", s, seg(segments[s]), (f in status && status[f] == "ok") ? sortms[f] : cell(f),
           (n in status && status[n] == "ok") ? sortms[n] : cell(n)
  }
  for (t = 1; t <= 2; t++) {
    mode = (t == 1) ? "opaque" : "kbuffer"; k = (t == 1) ? 0 : 4
    print ""
    if (t == 1) print "## Table 2a: opaque rendering, ms per frame"
    else print "## Table 2b: transparent rendering (k-buffer, k = 4), ms per frame"
    print ""
    print "A far, B far + culling, C far + culling + AO, D near, E near + culling, F near + culling + AO; speed-up of culling = A/B and D/E."
    print ""
    print "| data set | segments | A | B | C | D | E | F | A/B | D/E |"
    print "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for (i = 1; i <= nsets; i++) {
      s = order[i]; line = "| " s " | " seg(segments[s])
      for (v = 1; v <= 2; v++) {
        view = (v == 1) ? "far" : "near"
        line = line " | " cell(s "|" view "|" mode "|" k "|0|0") " | " cell(s "|" view "|" mode "|" k "|1|0") \
                    " | " cell(s "|" view "|" mode "|" k "|1|1")
      }
      line = line " | " ratio(s "|far|" mode "|" k "|0|0", s "|far|" mode "|" k "|1|0")
      line = line " | " ratio(s "|near|" mode "|" k "|0|0", s "|near|" mode "|" k "|1|0") " |"
      print line
    }
  }
  print ""
  print "## Table 3: k-buffer size, far view, ms per frame"
  print ""
  print "| data set | k=2 | k=4 | k=8 | k=16 | k=2 culling | k=4 culling | k=8 culling | k=16 culling |"
  print "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  for (i = 1; i <= nsets; i++) {
    s = order[i]; line = "| " s
    for (c = 0; c <= 1; c++)
      for (k = 2; k <= 16; k *= 2) line = line " | " cell(s "|far|kbuffer|" k "|" c "|0")
    print line " |"
  }
}' "$csv"
