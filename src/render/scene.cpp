#include "cgamesh/render/scene.hpp"

namespace cgamesh::render {

Box Scene::bounds() const {
  Box box;
  for (const DrawMesh& m : meshes)
    if (m.positions.rows() > 0) {
      box.add(m.positions.colwise().minCoeff().transpose().cast<double>());
      box.add(m.positions.colwise().maxCoeff().transpose().cast<double>());
    }
  for (const LineSet& l : lines)
    for (const Eigen::Vector3f& p : l.points) box.add(p.cast<double>());
  for (const PointSet& s : points)
    for (const Eigen::Vector3f& p : s.points) box.add(p.cast<double>());
  return box;
}

}  // namespace cgamesh::render
