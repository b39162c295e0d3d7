"""What scripts/bench/vtk_tubes.py and vtk_points.py share: an offscreen VTK window with tubecast's
camera and image size (from a run.json), depth peeling for transparent actors, and the timed
frames (one line per frame, then the median of the frames after the first).

Depth peeling and its limit. VTK 9.1 peels translucent geometry with vtkDualDepthPeelingPass
(two layers per peel, front and back), which stops when `CurrentPeel >= MaximumNumberOfPeels`
or when a peel's occlusion query counts <= OcclusionRatio x pixels; whatever is left after the
last peel is alpha blended in one unsorted pass. So vtkRenderer::SetMaximumNumberOfPeels(0),
documented as "no limit" for the older single-layer vtkDepthPeelingPass, means *zero peels* with
dual depth peeling: one depth-initialisation pass plus one unsorted alpha-blending pass, i.e.
not depth peeling at all (numbers measured with 0 are unsorted blending). No limit is therefore a large limit with occlusion ratio 0: peel until a peel
writes no pixel. The frames report how many geometry passes VTK really drew, counted with an
observer on the mapper's StartEvent (fired once per pass the mapper draws), and the peels that
implies.
"""
import json
import statistics
import time

import vtk

NO_PEEL_LIMIT = 1000000  # "no limit" for vtkDualDepthPeelingPass (see above)


def render_timed(actor, run_json, peel, frames, png=None, max_peels=None):
    """max_peels: None = no limit (NO_PEEL_LIMIT, occlusion ratio 0); otherwise passed to
    vtkRenderer::SetMaximumNumberOfPeels as is (0 = VTK's zero peels + alpha blending)."""
    run = json.load(open(run_json))
    cam = run["camera_first_frame"]
    width, height = run["image"]["width"], run["image"]["height"]

    ren = vtk.vtkRenderer()
    ren.AddActor(actor)
    ren.SetBackground(1, 1, 1)
    limit = NO_PEEL_LIMIT if max_peels is None else max_peels
    if peel:
        ren.SetUseDepthPeeling(1)
        ren.SetMaximumNumberOfPeels(limit)
        ren.SetOcclusionRatio(0.0)  # exact: peel until a peel writes no pixel
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(width, height)
    win.SetAlphaBitPlanes(1)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)

    # Geometry passes per frame: the mapper fires StartEvent each time a pass draws it.
    passes = [0]
    actor.GetMapper().AddObserver(vtk.vtkCommand.StartEvent, lambda *_: passes.__setitem__(0, passes[0] + 1))

    c = ren.GetActiveCamera()
    c.SetPosition(*cam["eye"])
    c.SetFocalPoint(*cam["target"])
    c.SetViewUp(*cam["up"])
    c.SetViewAngle(cam["fov_deg"])
    ren.ResetCameraClippingRange()

    print("renderer:", win.ReportCapabilities().splitlines()[1:3])
    if peel:
        print(f"depth peeling: vtkRenderer::SetMaximumNumberOfPeels({limit}), occlusion ratio 0")
    times = []
    for i in range(frames):
        c.Azimuth(0.5 if i else 0.0)  # a camera change per frame, as in an orbit
        ren.ResetCameraClippingRange()
        passes[0] = 0
        t0 = time.perf_counter()
        win.Render()
        win.WaitForCompletion()
        times.append(time.perf_counter() - t0)
        line = f"frame {i}: {times[-1]:.3f} s, {passes[0]} geometry passes"
        if peel and passes[0] == 0:
            line += " (this mapper fires no StartEvent per pass: peels not counted)"
        elif peel:
            # Dual depth peeling: 1 depth-initialisation pass, then one pass per peel; when the
            # limit (not the occlusion query) ended it, 1 more pass alpha blends the rest unsorted.
            stopped_by_limit = passes[0] - 2 == limit
            peels = limit if stopped_by_limit else passes[0] - 1
            line += f" = 1 depth init + {peels} peels"
            line += " + 1 unsorted alpha blend of the rest (peel limit reached: not exact)" if stopped_by_limit \
                else " (the last peel found nothing left: exact)"
        print(line, flush=True)
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
