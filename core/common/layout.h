// A texture layout: coordinates per face corner, the form MeshLab's wedge texture coordinates
// and geometry-central's CornerData take, so that a seam (one vertex, two coordinates) can be
// represented from the core to the file.
//   uv       #U x 2  the distinct texture coordinates, in the front end's frame
//   face_uv  #F x 3  per face of the input triangles and per corner k, the row of uv it carries:
//                    corner k of face f sits at uv.row(face_uv(f, k))
//   chart    #F or empty: a chart id per face (empty: all faces in one chart)
// A disk patch's layout is the special case U = #input vertices and face_uv = F: every corner of
// a vertex shares that vertex's row (unreferenced vertices keep a row, at 0, 0).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace sdp {

using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using UVs = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

struct Layout {
  UVs uv;
  Triangles face_uv;
  std::vector<int> chart;

  // The layout in which corner k of face f carries uv.row(F(f, k)): one coordinate per vertex.
  static Layout perVertex(UVs uv, const Triangles& F) {
    Layout layout;
    layout.uv = std::move(uv);
    layout.face_uv = F;
    return layout;
  }
  int faceCount() const { return static_cast<int>(face_uv.rows()); }
  Eigen::RowVector2d corner(int f, int k) const { return uv.row(face_uv(f, k)); }
};

}  // namespace sdp
