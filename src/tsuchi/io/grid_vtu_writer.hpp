#pragma once
// The grid frames (output.grid_fields): the background grid's nodal fields of a frame,
// solver/grid_projection.hpp's (P1), as a VTK XML UnstructuredGrid (binary, appended raw, UInt64
// block headers, as the particle frames) that ParaView's Plot Over Line, Probe, Slice and Contour
// work on. Its points are the nodes with mass (m_i > 0) and nothing else: a node no particle
// reaches has no value, and writing none keeps ParaView from drawing or interpolating zeros there
// (a line probed beyond the body gets vtkValidPointMask = 0, not a stress of 0). Its cells are the
// grid cells whose 2^D nodes all have mass (VTK_QUAD in 2D, VTK_HEXAHEDRON in 3D): the material's
// region and, with GIMP, up to a cell around it, where the nodes take the nearest particles'
// values. The cells only join points; the data are all on the points.
#include "tsuchi/model/model.hpp"
#include "tsuchi/solver/grid_projection.hpp"

#include <cstddef>
#include <string>

namespace tsuchi {

template <int D>
std::string grid_vtu_document(const Model<D>& model, const GridProjection<D>& projection);

// The points (nodes with mass) and cells (all 2^D nodes with mass) of a grid frame.
struct GridFrameSize {
  std::size_t points = 0, cells = 0;
  double bytes = 0.0;  // of the file, to within the digits of its offsets and counts
};
// From the projection of the model as it stands (one projection of the mass alone): the output
// size said before a run.
template <int D>
GridFrameSize grid_vtu_size(const Model<D>& model, const std::vector<std::string>& fields);

extern template std::string grid_vtu_document<2>(const Model<2>&, const GridProjection<2>&);
extern template std::string grid_vtu_document<3>(const Model<3>&, const GridProjection<3>&);
extern template GridFrameSize grid_vtu_size<2>(const Model<2>&, const std::vector<std::string>&);
extern template GridFrameSize grid_vtu_size<3>(const Model<3>&, const std::vector<std::string>&);

}  // namespace tsuchi
