#!/usr/bin/python3
"""The same lines rendered the way a VTK/ParaView user would: vtkTubeFilter (8 sides) and
depth peeling (no peel limit, occlusion ratio 0), offscreen under Xvfb on the same llvmpipe.

    xvfb-run -a -s "-screen 0 1920x1080x24" /usr/bin/python3 scripts/bench/vtk_tubes.py \
        LINES.vtp RUN.json --radius 0.0025 --opacity 0.3 --frames 3 [--opaque] [--png out.png]

LINES.vtp comes from `tubecast convert SCENE LINES.vtp`; RUN.json from a `tubecast render` of the
same scene (its camera_first_frame and image size are used, so both render the same view).
Prints one line per frame: "frame i: S s", then the median.
"""
import argparse
import json
import statistics
import time

import vtk


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
    args = ap.parse_args()

    run = json.load(open(args.run_json))
    cam = run["camera_first_frame"]
    width, height = run["image"]["width"], run["image"]["height"]

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

    ren = vtk.vtkRenderer()
    ren.AddActor(actor)
    ren.SetBackground(1, 1, 1)
    if not args.opaque:
        ren.SetUseDepthPeeling(1)
        ren.SetMaximumNumberOfPeels(0)  # no peel limit
        ren.SetOcclusionRatio(0.0)      # exact
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(width, height)
    win.SetAlphaBitPlanes(1)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)

    c = ren.GetActiveCamera()
    c.SetPosition(*cam["eye"])
    c.SetFocalPoint(*cam["target"])
    c.SetViewUp(*cam["up"])
    c.SetViewAngle(cam["fov_deg"])
    ren.ResetCameraClippingRange()

    print("renderer:", win.ReportCapabilities().splitlines()[1:3])
    times = []
    for i in range(args.frames):
        c.Azimuth(0.5 if i else 0.0)  # a camera change per frame, as in an orbit
        ren.ResetCameraClippingRange()
        t0 = time.perf_counter()
        win.Render()
        win.WaitForCompletion()
        times.append(time.perf_counter() - t0)
        print(f"frame {i}: {times[-1]:.3f} s")
    if args.png:
        w2i = vtk.vtkWindowToImageFilter()
        w2i.SetInput(win)
        w2i.Update()
        png = vtk.vtkPNGWriter()
        png.SetFileName(args.png)
        png.SetInputConnection(w2i.GetOutputPort())
        png.Write()
    steady = times[1:] if len(times) > 1 else times
    print(f"median (frames after the first): {statistics.median(steady):.3f} s")


if __name__ == "__main__":
    main()
