#include "polygon_triangulation.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cgamesh/errors.hpp"

#include "surgery_common.hpp"

namespace cgamesh::surgery::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceInfoBase = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;  // nesting level, -1 unset
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfoBase>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Constraints may meet at vertices; a proper crossing throws instead of inventing a vertex.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds,
                                                       CGAL::No_constraint_intersection_requiring_constructions_tag>;

/// Nesting level of every finite face: 0 outside all loops, +1 per constraint crossed (the
/// flood fill of CGAL's polygon-with-holes example).
void mark_nesting(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::deque<Cdt::Face_handle> border{cdt.infinite_face()};
  cdt.infinite_face()->info() = 0;
  int level = 0;
  while (!border.empty()) {
    std::deque<Cdt::Face_handle> next;
    while (!border.empty()) {
      const Cdt::Face_handle f = border.front();
      border.pop_front();
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info() != -1) continue;
        if (cdt.is_constrained(Cdt::Edge(f, i))) {
          next.push_back(n);
        } else {
          n->info() = level;
          border.push_back(n);
        }
      }
    }
    ++level;
    for (const Cdt::Face_handle f : next)
      if (f->info() == -1) {
        f->info() = level;
        border.push_back(f);
      }
  }
}

/// A CDT of the points with the edges as constraints.
void build_cdt(Cdt& cdt, std::span<const Eigen::Vector2d> points, std::span<const std::array<int, 2>> edges,
               const char* what) {
  std::vector<Cdt::Vertex_handle> handles(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto before = cdt.number_of_vertices();
    handles[i] = cdt.insert(Kernel::Point_2(points[i].x(), points[i].y()));
    // A point equal to an earlier one returns the earlier vertex, which keeps its index.
    if (cdt.number_of_vertices() > before) handles[i]->info() = static_cast<int>(i);
  }
  try {
    for (const auto& e : edges) {
      const Cdt::Vertex_handle a = handles[static_cast<std::size_t>(e[0])], b = handles[static_cast<std::size_t>(e[1])];
      // An edge between two points at one place (a zero-length edge of the section) is no
      // constraint: CGAL cannot constrain a vertex to itself.
      if (a != b) cdt.insert_constraint(a, b);
    }
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    throw TopologyError(what);
  }
}

}  // namespace

std::vector<std::array<int, 3>> triangulate_loops(std::span<const Eigen::Vector2d> points,
                                                  std::span<const std::array<int, 2>> edges) {
  Cdt cdt;
  build_cdt(cdt, points, edges, "cap: the cross-section loops cross each other; cannot triangulate the section");
  mark_nesting(cdt);
  std::vector<std::array<int, 3>> out;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 != 1) continue;
    out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return out;
}

std::vector<std::array<int, 3>> triangulate_loops_that_can_be(std::span<const Eigen::Vector2d> points,
                                                              std::span<const std::array<int, 2>> edges,
                                                              int& left_out) {
  left_out = 0;
  try {
    return triangulate_loops(points, edges);
  } catch (const TopologyError&) {
    // Find the loops that are to blame, below.
  }
  UnionFind components(points.size());
  for (const auto& e : edges) components.unite(e[0], e[1]);
  std::vector<int> loop_of(points.size(), -1);
  std::vector<std::vector<std::array<int, 2>>> loops;
  for (const auto& e : edges) {
    int& l = loop_of[static_cast<std::size_t>(components.find(e[0]))];
    if (l < 0) {
      l = static_cast<int>(loops.size());
      loops.emplace_back();
    }
    loops[static_cast<std::size_t>(l)].push_back(e);
  }
  const auto triangulates = [&](const std::vector<std::array<int, 2>>& set) {
    try {
      (void)triangulate_loops(points, set);
      return true;
    } catch (const TopologyError&) {
      return false;
    }
  };
  std::vector<char> keep(loops.size(), 0);
  std::vector<Eigen::AlignedBox2d> box(loops.size());
  for (std::size_t l = 0; l < loops.size(); ++l) {
    for (const auto& e : loops[l]) box[l].extend(points[static_cast<std::size_t>(e[0])]);
    keep[l] = triangulates(loops[l]) ? 1 : 0;
  }
  // Loops that cross each other: only pairs whose boxes meet can.
  for (std::size_t a = 0; a < loops.size(); ++a)
    for (std::size_t b = a + 1; b < loops.size(); ++b) {
      if (keep[a] == 0 || keep[b] == 0 || !box[a].intersects(box[b])) continue;
      std::vector<std::array<int, 2>> pair = loops[a];
      pair.insert(pair.end(), loops[b].begin(), loops[b].end());
      if (!triangulates(pair)) keep[a] = keep[b] = 0;
    }
  std::vector<std::array<int, 2>> kept;
  for (std::size_t l = 0; l < loops.size(); ++l)
    if (keep[l] != 0)
      kept.insert(kept.end(), loops[l].begin(), loops[l].end());
    else
      ++left_out;
  // Every crossing is within one loop or between two: the rest triangulate together.
  return triangulate_loops(points, kept);
}

std::vector<std::array<int, 3>> triangulate_constrained(std::span<const Eigen::Vector2d> points,
                                                        std::span<const std::array<int, 2>> segments) {
  Cdt cdt;
  build_cdt(cdt, points, segments, "the constrained segments cross each other");
  std::vector<std::array<int, 3>> out;
  out.reserve(cdt.number_of_faces());
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  return out;
}

}  // namespace cgamesh::surgery::detail
