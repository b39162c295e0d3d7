#!/usr/bin/python3
"""The same lines rendered the way a VTK/ParaView user would: vtkTubeFilter (8 sides) and
depth peeling (no peel limit, occlusion ratio 0; vtk_bench_common.py says why "no limit" is not
SetMaximumNumberOfPeels(0)), offscreen under Xvfb on the same llvmpipe.

    xvfb-run -a -s "-screen 0 1920x1080x24" /usr/bin/python3 scripts/bench/vtk_tubes.py \
        LINES.vtp RUN.json --radius 0.0025 --opacity 0.3 --frames 3 [--opaque] [--png out.png] [--max-peels N]

LINES.vtp comes from `tubecast convert SCENE LINES.vtp`; RUN.json from a `tubecast render` of the
same scene (its camera_first_frame and image size are used, so both render the same view).
Prints one line per frame: "frame i: S s, N geometry passes = 1 depth init + P peels ...", then
the median. Without a peel limit a frame of the 1M-segment tornado takes minutes: use --frames 1.
"""
import argparse
import time

import vtk

from vtk_bench_common import render_timed


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("lines")
    ap.add_argument("run_json")
    ap.add_argument("--radius", type=float, required=True)
    ap.add_argument("--opacity", type=float, default=0.3)
    ap.add_argument("--sides", type=int, default=8)
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--opaque", action="store_true")
    ap.add_argument("--png")
    ap.add_argument("--max-peels", type=int, default=None,
                    help="vtkRenderer::SetMaximumNumberOfPeels; default: no limit (see vtk_bench_common.py;"
                         " 0 = VTK's zero peels + unsorted alpha blending)")
    args = ap.parse_args()

    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(args.lines)
    tubes = vtk.vtkTubeFilter()
    tubes.SetInputConnection(reader.GetOutputPort())
    tubes.SetRadius(args.radius)
    tubes.SetNumberOfSides(args.sides)
    tubes.CappingOn()
    t0 = time.perf_counter()
    tubes.Update()
    print(f"tube filter: {time.perf_counter() - t0:.2f} s, {tubes.GetOutput().GetNumberOfCells()} cells")

    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(tubes.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.85, 0.55, 0.25)
    actor.GetProperty().SetOpacity(1.0 if args.opaque else args.opacity)

    render_timed(actor, args.run_json, not args.opaque, args.frames, args.png, args.max_peels)

if __name__ == "__main__":
    main()
