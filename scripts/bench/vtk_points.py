#!/usr/bin/python3
"""The same particles rendered the way a ParaView user renders millions of points:
vtkPointGaussianMapper with a sphere splat shader (ParaView's "Point Gaussian" representation,
shader preset "Sphere"), or vtkGlyph3DMapper with vtkSphereSource spheres, with depth peeling (no
peel limit, occlusion ratio 0) for opacity < 1, offscreen under Xvfb on the same llvmpipe.

    xvfb-run -a -s "-screen 0 1024x768x24" /usr/bin/python3 scripts/bench/vtk_points.py \
        PARTICLES.vtp RUN.json --opacity 0.3 --frames 3 [--glyph [--resolution 12]] [--png out.png]

PARTICLES.vtp comes from `tubecast convert SCENE PARTICLES.vtp` (a "radius" point array, vertex
cells); RUN.json from a `tubecast render` of the same scene (camera_first_frame and image size).
Prints one line per frame: "frame i: S s", then the median of the frames after the first.
"""
import argparse

import vtk

from vtk_bench_common import render_timed

# ParaView's "Sphere" splat: a shaded disc that reads as a sphere (Point Gaussian representation).
SPHERE_SPLAT = """//VTK::Color::Impl
float dist = dot(offsetVCVSOutput.xy, offsetVCVSOutput.xy);
if (dist > 1.0) {
  discard;
} else {
  float scale = (1.0 - dist);
  ambientColor *= scale;
  diffuseColor *= scale;
}
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("particles")
    ap.add_argument("run_json")
    ap.add_argument("--opacity", type=float, default=0.3)
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--glyph", action="store_true", help="vtkGlyph3DMapper with sphere sources")
    ap.add_argument("--resolution", type=int, default=12, help="sphere source theta/phi resolution (--glyph)")
    ap.add_argument("--png")
    ap.add_argument("--max-peels", type=int, default=None,
                    help="vtkRenderer::SetMaximumNumberOfPeels; default: no limit (see vtk_bench_common.py;"
                         " 0 = VTK's zero peels + unsorted alpha blending)")
    args = ap.parse_args()

    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(args.particles)
    reader.Update()
    points = reader.GetOutput()
    points.GetPointData().SetActiveScalars("radius")
    print(f"{points.GetNumberOfPoints()} particles")

    if args.glyph:
        sphere = vtk.vtkSphereSource()
        sphere.SetThetaResolution(args.resolution)
        sphere.SetPhiResolution(args.resolution)
        sphere.SetRadius(1.0)
        mapper = vtk.vtkGlyph3DMapper()
        mapper.SetInputData(points)
        mapper.SetSourceConnection(sphere.GetOutputPort())
        mapper.SetScaleArray("radius")
        mapper.SetScaleModeToScaleByMagnitude()
        mapper.ScalarVisibilityOff()
    else:
        mapper = vtk.vtkPointGaussianMapper()
        mapper.SetInputData(points)
        mapper.SetScaleArray("radius")
        mapper.SetScaleFactor(1.0)
        mapper.SetSplatShaderCode(SPHERE_SPLAT)
        mapper.EmissiveOff()
        mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.85, 0.55, 0.25)
    actor.GetProperty().SetOpacity(args.opacity)

    render_timed(actor, args.run_json, args.opacity < 1.0, args.frames, args.png, args.max_peels)

if __name__ == "__main__":
    main()
