# tests/faker/vtk_cone.py — a VTK 9 program (Debian's python3-vtk9), run by
# tests/faker/only_faker.sh natively and under `tessera exec`: a render
# window with a cone, rendered once, then read back. Prints the OpenGL
# version VTK got and how many pixels differ from the background; exits 0
# only if the cone was drawn, 1 if VTK found no usable OpenGL (its own
# message goes to stderr) or nothing was drawn. Uses VTK only.
import sys

from vtkmodules.vtkFiltersSources import vtkConeSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the OpenGL render window)

BACKGROUND = (0, 0, 0)

cone = vtkConeSource()
cone.SetResolution(24)
mapper = vtkPolyDataMapper()
mapper.SetInputConnection(cone.GetOutputPort())
actor = vtkActor()
actor.SetMapper(mapper)
renderer = vtkRenderer()
renderer.AddActor(actor)
renderer.SetBackground(*BACKGROUND)
window = vtkRenderWindow()
window.AddRenderer(renderer)
window.SetSize(160, 120)
if not window.SupportsOpenGL():
    print("vtk_cone: VTK finds no OpenGL 3.2 it can render with; nothing drawn")
    sys.exit(1)
window.Render()
version = [line for line in window.ReportCapabilities().splitlines() if line.startswith("OpenGL version string")]
print("vtk_cone: " + (version[0].strip() if version else "no OpenGL version reported"))

grab = vtkWindowToImageFilter()
grab.SetInput(window)
grab.Update()
image = grab.GetOutput()
scalars = image.GetPointData().GetScalars()
width, height, _ = image.GetDimensions()
drawn = sum(1 for i in range(width * height)
            if tuple(int(scalars.GetComponent(i, c)) for c in range(3)) != BACKGROUND)
print("vtk_cone: %d of %d pixels differ from the background" % (drawn, width * height))
sys.exit(0 if drawn > 0 else 1)
