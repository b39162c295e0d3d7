#!/usr/bin/env python3
"""Formatting steps of scripts/bench/report.sh: raw benchmark output to the Markdown tables of
docs/performance.md, the tables into the document, and the document's tables into charts.

    report_format.py vrc-memory|vrc-frames FILE...     vrc_tables.sh output
    report_format.py opacity FILE...                   opacity_tables.sh output
    report_format.py batch FILE DIR                    batch_throughput.sh output, its output DIR
    report_format.py replace DOC BLOCKDIR              every BLOCKDIR/NAME.md between the markers
                                                       <!-- report:NAME --> and <!-- /report:NAME -->
    report_format.py charts DOC IMAGEDIR BLOCKDIR      charts (gnuplot) from DOC's tables; writes
                                                       the chart blocks into BLOCKDIR
"""
import glob
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def number(text):
    m = re.match(r"[>~]?\s*([0-9][0-9,]*\.?[0-9]*)", text.strip())
    return float(m.group(1).replace(",", "")) if m else None


def span(values, fmt="{:.0f}"):
    values = sorted(values)
    if not values:
        return "-"
    a, b = fmt.format(values[0]), fmt.format(values[-1])
    return a if a == b else f"{a}-{b}"


# --- vrc_tables.sh -------------------------------------------------------------------------------

def vrc_runs(files):
    """{(set, name): {"frame1": ms, "stats": {...}}} from vrc_tables.sh lines
    'SET NAME user/sys/wall s U S W :: frame0=.. stage=.. frame1=..  || key=value, ...'."""
    runs = {}
    for path in files:
        for line in open(path):
            m = re.match(r"(\S+) (\S+) user/sys/wall s [\d.]+ [\d.]+ [\d.]+ :: (.*?)(?:\|\|(.*))?$", line.strip())
            if not m:
                continue
            stages = dict(kv.split("=", 1) for kv in m.group(3).split())
            stats = dict(kv.strip().split("=", 1) for kv in (m.group(4) or "").split(",") if "=" in kv)
            label = m.group(1)
            if "segments" in stats and int(stats["segments"]) > 6_000_000:
                label += f" ({int(stats['segments']) / 1e6:.0f}M segments)"
            runs[(label, m.group(2))] = {"frame1": stages.get("frame1"), "stats": stats}
    return runs


def vrc_memory(files):
    runs = vrc_runs(files)
    print("| data set | segments | pieces (of which copies) | B / piece | model MB | raw lines MB | model build ms |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for (label, name), r in runs.items():
        if name != "vrc_transparent":
            continue
        s = r["stats"]
        builds = [float(runs[(label, n)]["stats"]["build_ms"]) for n in ("vrc_opaque", "vrc_transparent")
                  if (label, n) in runs and "build_ms" in runs[(label, n)]["stats"]]
        blocks = f" ({s['piece_blocks']} blocks)" if int(s.get("piece_blocks", 1)) > 1 else ""
        print(f"| {label} | {int(s['segments']):,} | {int(s['pieces']):,} ({int(s['copies']):,}) | {s['bytes_per_piece']} "
              f"| {float(s['model_mb']):.1f}{blocks} | {float(s['raw_lines_mb']):.1f} | {span(builds)} |")


def vrc_frames(files):
    runs = vrc_runs(files)
    print("| data set | rasterized opaque | VRC opaque | k-buffer k=8 | depth peeling | VRC transparent | VRC / k-buffer |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label in dict.fromkeys(k[0] for k in runs):
        ms = {n: runs[(label, n)]["frame1"] if (label, n) in runs else None
              for n in ("raster_opaque", "vrc_opaque", "kbuffer", "depth_peeling", "vrc_transparent")}
        show = {n: f"{float(v):,.0f}" if v else "-" for n, v in ms.items()}
        ratio = f"{float(ms['kbuffer']) / float(ms['vrc_transparent']):.2f}x" if ms["kbuffer"] and ms["vrc_transparent"] else "-"
        print(f"| {label} | {show['raster_opaque']} | {show['vrc_opaque']} | {show['kbuffer']} | {show['depth_peeling']} "
              f"| {show['vrc_transparent']} | {ratio} |")


# --- opacity_tables.sh ---------------------------------------------------------------------------

def opacity(files):
    print("| parts | occlusion | fragments | lists ms | read-back + sort ms | h ms | frame 0: cold solve ms (products) "
          "| warm frames: solve ms (products) | warm solves / s (median) |")
    print("|---:|---|---:|---:|---:|---:|---:|---|---|")
    solve = re.compile(r"([\d.]+) \((\d+), (\d+), [^)]*\)")
    for path in files:
        section = None
        for line in open(path).read().splitlines() + ["### end"]:
            head = re.match(r"### (\d+) parts, occlusion (\S+), occlusion_scale ([\d.]+)", line)
            if head or line.startswith("### end"):
                if section and section["first"]:
                    f0 = section["first"]
                    rows = section["next"]
                    lists = [number(f0[5])] + [number(r[4]) for r in rows]
                    sort = [number(f0[6])] + [number(r[5]) for r in rows]
                    h = [number(f0[7])] + [number(r[6]) for r in rows]
                    cold = solve.match(f0[8])
                    warm = [solve.match(r[7]) for r in rows]
                    warm_ms = [float(w.group(1)) for w in warm if w]
                    warm_p = [int(w.group(3)) for w in warm if w]
                    rates = [1000.0 / v for v in warm_ms if v > 0]
                    occl = f0[1] + (f", scale {section['scale']}" if section["scale"] != "1" else "")
                    warm_cells = (f"{span(warm_ms, '{:.1f}')} ({span(warm_p)}) | {span(rates, '{:.1f}')} "
                                  f"({statistics.median(rates):.1f})") if rates else "- | -"
                    print(f"| {f0[0]} | {occl} | {f0[2]} | {span(lists)} | {span(sort)} | {span(h)} "
                          f"| {float(cold.group(1)):.1f} ({cold.group(3)}) | {warm_cells} |")
                section = head and {"occlusion": head.group(2), "scale": head.group(3), "first": None, "next": []}
                continue
            if section is None or not line.startswith("|") or line.startswith("|---") or "parts |" in line:
                continue
            c = cells(line)
            if len(c) == 14 and section["first"] is None:
                section["first"] = c
            elif len(c) == 10:
                section["next"].append(c)


# --- batch_throughput.sh -------------------------------------------------------------------------

def batch(path, outdir):
    text = open(path).read()
    def median_frame(pattern):
        ms = []
        for csv in glob.glob(os.path.join(outdir, pattern)):
            for line in open(csv):
                f = line.strip().split(",")
                if len(f) >= 4 and f[1] == "frame" and f[0] != "frame":
                    ms.append(float(f[3]))
        return f"{statistics.median(ms):.0f}" if ms else "-"
    def load_style(name):
        m = re.search(rf"^{name} load_and_style_s: (.*)$", text, re.M)
        vals = re.findall(r'"load_and_style_s":([\d.]+)', m.group(1)) if m else []
        return ", ".join(f"{float(v):.2f}" for v in vals) or "-"
    rows = [("1 process, 2 llvmpipe threads", r"^1 process.*?: ([\d.]+) s for (\d+) frames", "one", "one/timings*.csv"),
            ("2 shards, `taskset` 1 CPU each", r"^2 shards.*?: ([\d.]+) s for (\d+) frames", "two", "two/timings*.csv"),
            ("2 Slurm array tasks, 1 CPU each", r"^2 Slurm array tasks.*?: ([\d.]+) s for (\d+) frames", "slurm",
             "slurm/timings*.csv")]
    print("| configuration | wall (s) | frames / hour | load + style per process (s) | median `frame` (ms) |")
    print("|---|---:|---:|---:|---:|")
    for label, pattern, name, csvs in rows:
        m = re.search(pattern, text, re.M)
        if not m:
            skipped = re.search(r"^Slurm run skipped: (.*)$", text, re.M) if name == "slurm" else None
            if skipped:
                print(f"| {label} | not run: {skipped.group(1)} | | | |")
            continue
        wall, frames = float(m.group(1)), int(m.group(2))
        print(f"| {label} | {wall:.1f} | {frames * 3600 / wall:.0f} | {load_style(name)} | {median_frame(csvs)} |")


# --- the document --------------------------------------------------------------------------------

BLOCK = re.compile(r"(<!-- report:([a-z_0-9]+) -->\n)(.*?)(<!-- /report:\2 -->)", re.S)


def replace(doc, blockdir):
    text = open(doc).read()
    done = []
    def fill(m):
        path = os.path.join(blockdir, m.group(2) + ".md")
        if not os.path.exists(path):
            return m.group(0)
        done.append(m.group(2))
        body = open(path).read().rstrip("\n") + "\n"
        return m.group(1) + body + m.group(4)
    text = BLOCK.sub(fill, text)
    open(doc, "w").write(text)
    missing = sorted(set(os.path.basename(p)[:-3] for p in glob.glob(os.path.join(blockdir, "*.md"))) - set(done))
    print(f"report_format.py: {doc}: {len(done)} blocks rewritten" +
          (f"; no marker for: {', '.join(missing)}" if missing else ""), file=sys.stderr)


def block_table(text, name, index=0):
    """The rows (lists of cells) of table INDEX (0 = the first) in block NAME, header first."""
    m = re.search(rf"<!-- report:{name} -->\n(.*?)<!-- /report:{name} -->", text, re.S)
    if not m:
        return []
    tables, current = [], []
    for line in m.group(1).splitlines() + [""]:
        if line.startswith("|"):
            if not line.startswith("|--"):
                current.append(cells(line))
        elif current:
            tables.append(current)
            current = []
    return tables[index] if index < len(tables) else []


def gnuplot(script, out):
    r = subprocess.run(["gnuplot"], input=script, text=True, capture_output=True)
    if r.returncode != 0 or not os.path.exists(out):
        print(f"report_format.py: gnuplot failed for {out}:\n{r.stderr}", file=sys.stderr)
        return False
    return True


TERMINAL = 'set terminal pngcairo size 640,400 font ",9" noenhanced\n'


def chart_culling(text, imagedir, tmp):
    """Culling speed-up (A/B far, D/E near) per data set, opaque and k-buffer (the paper tables)."""
    data = {}
    for mode, index in (("opaque", 1), ("k-buffer", 2)):  # block "paper": Tables 1, 2a, 2b, 3
        rows = block_table(text, "paper", index)
        for r in rows[1:]:
            far, near = number(r[-2]), number(r[-1])
            if far is None or near is None:
                return None
            data.setdefault(r[0], {})[mode] = (far, near)
    if not data:
        return None
    dat = os.path.join(tmp, "culling.dat")
    with open(dat, "w") as f:
        f.write('set "opaque, far" "opaque, near" "k-buffer, far" "k-buffer, near"\n')
        for s, v in data.items():
            if len(v) == 2:
                f.write(f"{s} {v['opaque'][0]} {v['opaque'][1]} {v['k-buffer'][0]} {v['k-buffer'][1]}\n")
    out = os.path.join(imagedir, "perf_culling.png")
    ok = gnuplot(TERMINAL + f'''set output "{out}"
set title "Speed-up of render.culling (frame time without / with), 960x540"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set grid ytics
set ylabel "speed-up (x)"
set yrange [0:*]
set key top left
set arrow from graph 0, first 1 to graph 1, first 1 nohead dt 2
plot for [c=2:5] "{dat}" using c:xtic(1) title columnheader(c)
''', out)
    return ("![Culling speed-up per data set, far and near views](images/perf_culling.png)", out) if ok else None


def chart_kbuffer(text, imagedir, tmp):
    """The k sweep: frame time and PSNR against depth peeling per k (transparency table)."""
    rows = []
    for r in block_table(text, "transparency")[1:]:
        m = re.match(r"k-buffer k=(\d+)", r[0])
        if m and number(r[1]) is not None and number(r[3]) is not None:
            rows.append((int(m.group(1)), number(r[1]), number(r[3])))
    if len(rows) < 2:
        return None
    dat = os.path.join(tmp, "kbuffer.dat")
    with open(dat, "w") as f:
        for k, ms, psnr in rows:
            f.write(f"{k} {ms} {psnr}\n")
    out = os.path.join(imagedir, "perf_kbuffer.png")
    ok = gnuplot(TERMINAL + f'''set output "{out}"
set title "k-buffer size: PSNR against depth peeling and frame time (1M tornado)"
set logscale x 2
set xlabel "k (fragments kept per pixel)"
set ylabel "PSNR (dB, 480x270)"
set y2label "ms per frame (1920x1080)"
set ytics nomirror
set y2tics
set grid xtics ytics
set key bottom right
plot "{dat}" using 1:3 with linespoints lw 2 title "PSNR", "{dat}" using 1:2 axes x1y2 with linespoints lw 2 dt 2 title "ms per frame"
''', out)
    return ("![PSNR and frame time against k](images/perf_kbuffer.png)", out) if ok else None


def chart_scaling(text, imagedir, tmp):
    """Frame time against segment count per technique (scaling table)."""
    rows = block_table(text, "scaling")
    if len(rows) < 3:
        return None
    header, body = rows[0], rows[1:]
    if any(number(c) is None for r in body for c in r[1:]):
        body = [r for r in body if all(number(c) is not None for c in r[1:])]
    if len(body) < 2:
        return None
    dat = os.path.join(tmp, "scaling.dat")
    with open(dat, "w") as f:
        f.write(" ".join(f'"{h}"' for h in header) + "\n")
        for r in body:
            f.write(" ".join(str(number(c)) for c in r) + "\n")
    out = os.path.join(imagedir, "perf_scaling.png")
    ok = gnuplot(TERMINAL + f'''set output "{out}"
set title "Time per frame against segment count (tornado, 1920x1080)"
set logscale xy
set xlabel "segments"
set ylabel "ms per frame"
set grid xtics ytics mxtics mytics
set key top left
plot for [c=2:{len(header)}] "{dat}" using 1:c with linespoints lw 2 title columnheader(c)
''', out)
    return ("![Frame time against segment count per technique](images/perf_scaling.png)", out) if ok else None


def charts(doc, imagedir, blockdir):
    text = open(doc).read()
    os.makedirs(imagedir, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for name, make in (("chart_culling", chart_culling), ("chart_kbuffer", chart_kbuffer),
                           ("chart_scaling", chart_scaling)):
            made = make(text, imagedir, tmp)
            if made:
                with open(os.path.join(blockdir, name + ".md"), "w") as f:
                    f.write(made[0] + "\n")
                print(f"report_format.py: {made[1]}", file=sys.stderr)
            else:
                print(f"report_format.py: {name}: no complete table to draw from", file=sys.stderr)


def main():
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "vrc-memory":
        vrc_memory(args)
    elif cmd == "vrc-frames":
        vrc_frames(args)
    elif cmd == "opacity":
        opacity(args)
    elif cmd == "batch":
        batch(args[0], args[1])
    elif cmd == "replace":
        replace(args[0], args[1])
    elif cmd == "charts":
        charts(args[0], args[1], args[2])
    else:
        sys.exit(f"report_format.py: unknown step {cmd}")


if __name__ == "__main__":
    main()
