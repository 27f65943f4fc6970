#pragma once
// particles_view.py: a ParaView Python state written beside particles.pvd, so that a run's frames
// open as a user wants to see them (issue 41): at the last frame, each particle a disc or sphere of
// its own size (Point Gaussian scaled by "radius"), coloured by max_shear_strain over the range of
// every frame (ParaView's own default opened at t = 0 with a range of 0 to 1.2e-38 that stayed).
// It names no absolute path: the directory may be moved or copied, and a restarted run writes the
// same bytes as an uninterrupted one.
#include <string>
#include <vector>

namespace tsuchi {

// The script for frames of `dimension` holding `fields` (output.fields), in cells of `cell_size`;
// with `grid_frames` (output.grid_fields), it also opens grid.pvd, not shown, for the filters that
// need cells (Plot Over Line, Probe, Slice, Contour).
std::string paraview_view_script(int dimension, const std::vector<std::string>& fields, double cell_size,
                                 bool grid_frames);

}  // namespace tsuchi
