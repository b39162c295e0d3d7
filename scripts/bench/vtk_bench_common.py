"""What scripts/bench/vtk_tubes.py and vtk_points.py share: an offscreen VTK window with tubecast's
camera and image size (from a run.json), depth peeling without limit for transparent actors, and
the timed frames (one line per frame, then the median of the frames after the first)."""
import json
import statistics
import time

import vtk


def render_timed(actor, run_json, peel, frames, png=None):
    run = json.load(open(run_json))
    cam = run["camera_first_frame"]
    width, height = run["image"]["width"], run["image"]["height"]

    ren = vtk.vtkRenderer()
    ren.AddActor(actor)
    ren.SetBackground(1, 1, 1)
    if peel:
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
    for i in range(frames):
        c.Azimuth(0.5 if i else 0.0)  # a camera change per frame, as in an orbit
        ren.ResetCameraClippingRange()
        t0 = time.perf_counter()
        win.Render()
        win.WaitForCompletion()
        times.append(time.perf_counter() - t0)
        print(f"frame {i}: {times[-1]:.3f} s", flush=True)
    if peel:
        print("depth peeling used:", bool(ren.GetLastRenderingUsedDepthPeeling()))
    if png:
        w2i = vtk.vtkWindowToImageFilter()
        w2i.SetInput(win)
        w2i.Update()
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(png)
        writer.SetInputConnection(w2i.GetOutputPort())
        writer.Write()
    steady = times[1:] if len(times) > 1 else times
    print(f"median (frames after the first): {statistics.median(steady):.3f} s")
