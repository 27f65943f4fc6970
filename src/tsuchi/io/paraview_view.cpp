#include "tsuchi/io/paraview_view.hpp"

#include "tsuchi/core/version.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace tsuchi {

std::string paraview_view_script(int dimension, const std::vector<std::string>& fields, double cell_size,
                                 bool grid_frames) {
  const auto has = [&](const char* f) { return std::find(fields.begin(), fields.end(), f) != fields.end(); };
  // The colour: where the shear bands are, else the first of the usual scalars the frames hold.
  std::string colour;
  for (const char* f : {"max_shear_strain", "deviator_stress", "mean_stress", "plastic_shear_strain"})
    if (has(f)) {
      colour = f;
      break;
    }
  const std::string size =
      has("radius") ? "display.ScaleByArray = 1\n"
                      "display.SetScaleArray = ['POINTS', 'radius']\n"
                      "display.UseScaleFunction = 0  # the array's values as they are: radius in m\n"
                      "display.GaussianRadius = 1.0\n"
                    : fmt::format("display.GaussianRadius = {:.6g}  # a quarter cell: the frames hold no 'radius'\n",
                                  0.25 * cell_size);
  const std::string colouring =
      colour.empty()
          ? std::string("ColorBy(display, None)\n")
          : fmt::format("ColorBy(display, ('POINTS', '{0}'))\n"
                        "# The range of every frame, kept as the frames are stepped through.\n"
                        "display.RescaleTransferFunctionToDataRangeOverTime()\n"
                        "GetColorTransferFunction('{0}').AutomaticRescaleRangeMode = 'Never'\n"
                        "display.SetScalarBarVisibility(view, True)\n",
                        colour);
  // grid.pvd: its own source, since in particles.pvd as a second part it would make the particles a
  // multiblock that shares their display (Point Gaussian discs at the nodes, one colour map).
  const std::string grid =
      "# The grid frames (output.grid_fields): the particles' fields projected to the grid's nodes, with\n"
      "# cells where the nodes have mass. Loaded, not shown: select 'grid.pvd' in the Pipeline Browser\n"
      "# for Plot Over Line, Probe, Slice or Contour, which need cells (a particle is a vertex).\n"
      "_grid = os.path.join(_directory(), 'grid.pvd')\n"
      "if os.path.exists(_grid):\n"
      "    grid = PVDReader(registrationName='grid.pvd', FileName=_grid)\n"
      "    SetActiveSource(particles)\n";
  return fmt::format(
      R"(# ParaView view of the particle frames in this directory, written by tsuchi {version}.
# Open it in ParaView (5.9 or later): File > Load State..., choose this file (a Python state file,
# and "Search files under specified directory" is not needed); or from a shell in this directory:
#     paraview --script=particles_view.py
# It opens particles.pvd at its last frame, each particle drawn as a {shape} of its own size (Point
# Gaussian, scaled by the 'radius' field), coloured by {colour_said} over the range of all frames.
# Units and sign conventions are in each frame's field data ('units', 'conventions'): stresses are
# in Pa, tension positive. Points are in the order of the 'id' field in every frame, so filters
# that follow points by index agree with it; for pathlines take Temporal Particles To Pathlines
# with Id Channel Array = 'id'.
import os
from paraview.simple import *

def _directory():
    try:
        return os.path.dirname(os.path.abspath(__file__))
    except NameError:  # run where __file__ is not set: the working directory
        return os.getcwd()

_pvd = os.path.join(_directory(), 'particles.pvd')
if not os.path.exists(_pvd):
    raise RuntimeError('tsuchi: particles.pvd is not beside this script (looked for ' + _pvd + ')')
particles = PVDReader(registrationName='particles.pvd', FileName=_pvd)
view = GetActiveViewOrCreate('RenderView')
display = Show(particles, view)
display.SetRepresentationType('Point Gaussian')
display.ShaderPreset = '{preset}'
{size}{grid}
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
try:
    _times = list(particles.TimestepValues)
except TypeError:  # a single frame: one number
    _times = [particles.TimestepValues]
if _times:
    scene.AnimationTime = _times[-1]
{colouring}{camera}view.ResetCamera()
Render()
)",
      fmt::arg("version", version), fmt::arg("shape", dimension == 2 ? "disc" : "sphere"),
      fmt::arg("colour_said", colour.empty() ? "nothing (no scalar field chosen)" : colour),
      fmt::arg("preset", dimension == 2 ? "Plain circle" : "Sphere"), fmt::arg("size", size),
      fmt::arg("colouring", colouring), fmt::arg("grid", grid_frames ? grid : std::string{}),
      fmt::arg("camera", dimension == 2 ? "view.InteractionMode = '2D'  # plane strain: the x-y plane\n" : ""));
}

}  // namespace tsuchi
