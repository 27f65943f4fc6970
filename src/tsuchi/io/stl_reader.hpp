#pragma once
// Reads the triangles of an STL file, ASCII or binary. A binary file is recognised by its size
// (84 bytes of header and count, then 50 bytes per triangle), since many binary files also begin
// with the word "solid"; anything else must be ASCII: `solid NAME`, then per triangle
// `facet normal nx ny nz / outer loop / vertex x y z (three times) / endloop / endfacet`, then
// `endsolid`. Normals are not read: the orientation comes from the order of the vertices.
#include "tsuchi/geometry/triangle_mesh.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace tsuchi::io {

// What is wrong with the file, in words naming the line or the byte (no file name: the caller
// adds it with the input's key).
struct StlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct StlSurface {
  std::vector<geometry::Triangle> triangles;
  // Where triangle k starts: its line in an ASCII file, its byte offset in a binary one.
  std::vector<std::size_t> start;
  bool binary = false;
  // "triangle 4 (line 23)" or "triangle 4 (byte 234)", k from 0, printed from 1.
  std::string name(std::size_t k) const;
};

// Files above this size are refused before they are read (some 20 million triangles in binary).
inline constexpr std::uint64_t max_stl_bytes = std::uint64_t{1} << 30;

StlSurface read_stl(const std::string& path);

}  // namespace tsuchi::io
