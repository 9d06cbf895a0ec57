#!/usr/bin/python3
"""Frame time of VTK's vtkGPUVolumeRayCastMapper on a raw volume, for ropecast's side-by-side benchmark.

Renders offscreen (run under xvfb-run) at the given size with half-voxel sampling, orbiting the camera a little
each frame so nothing is cached between frames, and prints one JSON line with the median frame time.

  xvfb-run -a /usr/bin/python3 bench/vtk_raycast.py VOLUME.raw --dims 256,256,256 --mode iso --iso 127.5

--orbit AZ,EL,DIST and --fov place the camera exactly as `ropecast render --orbit` does (core/camera.cpp
orbitCamera: around the box [0, n] with voxel i's center at i + 0.5, distance in bounding-sphere radii, z up);
each measured frame then turns the azimuth by --turn degrees. --tf FILE reads a ropecast transfer function
JSON ({"points": [[value, r, g, b, a], ...]}, values in stored units for uint8/uint16 data) so both renderers
use the same color and opacity (opacity per unit length = per voxel at spacing 1, as ropecast's correction).
"""
import math
import argparse
import json
import statistics
import sys
import time

import vtk


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("raw")
    ap.add_argument("--dims", required=True)
    ap.add_argument("--type", default="uint8", choices=["uint8", "uint16"])
    ap.add_argument("--mode", default="iso", choices=["iso", "dvr"])
    ap.add_argument("--iso", type=float, default=127.5)
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--orbit", help="AZ,EL,DIST as ropecast render --orbit (default: VTK's ResetCamera framing)")
    ap.add_argument("--fov", type=float, default=40.0)
    ap.add_argument("--turn", type=float, default=1.0, help="azimuth degrees added per frame")
    ap.add_argument("--tf", help="ropecast transfer function JSON for --mode dvr")
    ap.add_argument("--screenshot", help="write the last frame as PNG, to check what was measured")
    args = ap.parse_args()
    nx, ny, nz = (int(v) for v in args.dims.split(","))
    w, h = (int(v) for v in args.size.split("x"))

    reader = vtk.vtkImageReader2()
    reader.SetFileName(args.raw)
    reader.SetDataScalarType(vtk.VTK_UNSIGNED_CHAR if args.type == "uint8" else vtk.VTK_UNSIGNED_SHORT)
    reader.SetDataByteOrderToLittleEndian()
    reader.SetFileDimensionality(3)
    reader.SetDataExtent(0, nx - 1, 0, ny - 1, 0, nz - 1)
    reader.SetNumberOfScalarComponents(1)
    reader.SetDataOrigin(0.5, 0.5, 0.5)  # voxel i's center at i + 0.5, as in ropecast's world
    reader.Update()

    mapper = vtk.vtkGPUVolumeRayCastMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.AutoAdjustSampleDistancesOff()
    mapper.SetSampleDistance(0.5)  # half a voxel (spacing 1)
    mapper.SetUseJittering(False)

    color = vtk.vtkColorTransferFunction()
    opacity = vtk.vtkPiecewiseFunction()
    prop = vtk.vtkVolumeProperty()
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    prop.SetAmbient(0.15)
    prop.SetDiffuse(0.75)
    prop.SetSpecular(0.25)
    prop.SetSpecularPower(32)
    vmax = 255.0 if args.type == "uint8" else 65535.0
    if args.mode == "iso":
        mapper.SetBlendModeToIsoSurface()
        prop.GetIsoSurfaceValues().SetValue(0, args.iso)
        color.AddRGBPoint(0, 0.9, 0.85, 0.75)
        color.AddRGBPoint(vmax, 0.9, 0.85, 0.75)
        opacity.AddPoint(0, 1.0)
        opacity.AddPoint(vmax, 1.0)
    elif args.tf:
        mapper.SetBlendModeToComposite()
        with open(args.tf) as f:
            for value, r, g, b, a in json.load(f)["points"]:
                color.AddRGBPoint(value, r, g, b)
                opacity.AddPoint(value, a)
    else:
        mapper.SetBlendModeToComposite()
        color.AddRGBPoint(0, 0.0, 0.0, 0.0)
        color.AddRGBPoint(0.3 * vmax, 0.8, 0.5, 0.3)
        color.AddRGBPoint(vmax, 1.0, 1.0, 0.9)
        opacity.AddPoint(0, 0.0)
        opacity.AddPoint(0.3 * vmax, 0.0)
        opacity.AddPoint(0.5 * vmax, 0.05)
        opacity.AddPoint(vmax, 0.3)
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)

    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    renderer = vtk.vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0, 0, 0)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(w, h)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()

    def place_camera(frame):
        if not args.orbit:
            if frame == 0:
                renderer.ResetCamera()
                camera.SetViewAngle(args.fov)
                camera.Azimuth(30)
                camera.Elevation(20)
            camera.Azimuth(args.turn)
        else:
            az, el, dist = (float(v) for v in args.orbit.split(","))
            az, el = math.radians(az + args.turn * frame), math.radians(el)
            center = (0.5 * nx, 0.5 * ny, 0.5 * nz)
            radius = 0.5 * math.sqrt(nx * nx + ny * ny + nz * nz)
            d = (math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el))
            camera.SetFocalPoint(*center)
            camera.SetPosition(*(c + dist * radius * di for c, di in zip(center, d)))
            camera.SetViewUp(0, 0, 1)
            camera.SetViewAngle(args.fov)
        renderer.ResetCameraClippingRange()

    times = []
    for i in range(args.warmup + args.frames):
        place_camera(i)
        t0 = time.perf_counter()
        window.Render()
        window.WaitForCompletion()
        dt = (time.perf_counter() - t0) * 1000.0
        if i >= args.warmup:
            times.append(dt)
    if args.screenshot:
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        png = vtk.vtkPNGWriter()
        png.SetFileName(args.screenshot)
        png.SetInputConnection(grab.GetOutputPort())
        png.Write()
    caps = window.ReportCapabilities().splitlines()
    gl_renderer = next((line.split(":", 1)[1].strip() for line in caps if "OpenGL renderer string" in line), "")
    print(json.dumps({"renderer": "vtkGPUVolumeRayCastMapper", "gl_renderer": gl_renderer, "mode": args.mode,
                      "size": args.size,
                      "frames": args.frames, "median_ms": statistics.median(times), "min_ms": min(times)}))


if __name__ == "__main__":
    sys.exit(main())
