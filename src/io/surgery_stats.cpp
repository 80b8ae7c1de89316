#include "cgamesh/io/surgery_stats.hpp"

#include <nlohmann/json.hpp>

namespace cgamesh::io {

using Json = nlohmann::ordered_json;

std::string stats_json(const surgery::CutStats& s) {
  return Json{{"new_vertices", s.new_vertices},
              {"intersection_points", s.intersection_points},
              {"faces_in", s.faces_in},
              {"faces_split", s.faces_split},
              {"cap_triangles", s.cap_triangles}}
      .dump();
}

std::string stats_json(const surgery::TearStats& s) {
  Json path = Json::array();
  for (const Eigen::Vector3d& p : s.path) path.push_back({p.x(), p.y(), p.z()});
  return Json{{"new_vertices", s.new_vertices},
              {"intersection_points", s.intersection_points},
              {"faces_in", s.faces_in},
              {"faces_out", s.faces_out},
              {"faces_split", s.faces_split},
              {"path", path}}
      .dump();
}

std::string stats_json(const surgery::DrillStats& s) {
  return Json{{"new_vertices", s.new_vertices},
              {"intersection_points", s.intersection_points},
              {"faces_in", s.faces_in},
              {"faces_out", s.faces_out},
              {"faces_removed", s.faces_removed},
              {"faces_affected", s.faces_affected},
              {"refinements", s.refinements},
              {"rims", s.rims},
              {"walls", s.walls},
              {"open_rims", s.open_rims},
              {"wall_triangles", s.wall_triangles}}
      .dump();
}

}  // namespace cgamesh::io
