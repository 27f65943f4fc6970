#pragma once
// VTK XML UnstructuredGrid (.vtu) documents of the particles, binary ("appended raw" with UInt64
// block headers), one vertex cell per particle, and the .pvd collection that makes a time series
// of them for ParaView.
#include "tsuchi/model/model.hpp"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace tsuchi {

// The whole .vtu file for the given fields (names from particle_fields.hpp).
template <int D>
std::string vtu_document(const Model<D>& model, const std::vector<std::string>& fields);

// The size of the .vtu file of `model` for the given fields, from the particle count without
// building the document (to within the digits of its offsets): the output size said before a run.
template <int D>
double vtu_size(const Model<D>& model, const std::vector<std::string>& fields);

// The grid nodes where contact acted (ExplicitSolver::contact_nodes()), as vertices with the
// normal, the contact force and the kind (1: between bodies, 2: a wall, 3: both), for ParaView.
struct ContactPoints {
  std::vector<std::array<double, 3>> x, normal, force;
  std::vector<int> kind;
};
std::string contact_vtu_document(const ContactPoints& points);

// A .pvd listing (time, file name) pairs.
std::string pvd_document(const std::vector<std::pair<double, std::string>>& frames);

extern template std::string vtu_document<2>(const Model<2>&, const std::vector<std::string>&);
extern template std::string vtu_document<3>(const Model<3>&, const std::vector<std::string>&);
extern template double vtu_size<2>(const Model<2>&, const std::vector<std::string>&);
extern template double vtu_size<3>(const Model<3>&, const std::vector<std::string>&);

}  // namespace tsuchi
