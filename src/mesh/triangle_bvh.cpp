#include "cgamesh/mesh/triangle_bvh.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cgamesh/errors.hpp"

namespace cgamesh::mesh {
namespace {

constexpr int kLeafSize = 4;

}  // namespace

TriangleBvh::TriangleBvh(const RowMatrixXf<3>& positions, const Faces& faces) {
  const Eigen::Index nf = faces.rows();
  if (nf > 0 && (faces.minCoeff() < 0 || faces.maxCoeff() >= positions.rows()))
    throw InvalidInputError("TriangleBvh: a face refers to a vertex outside the " + std::to_string(positions.rows()) +
                            " positions");
  if (!positions.allFinite()) throw InvalidInputError("TriangleBvh: the placed positions hold NaN or infinity");
  corners_.resize(static_cast<std::size_t>(3 * nf));
  std::vector<Eigen::Vector3f> centroids(static_cast<std::size_t>(nf));
  order_.resize(static_cast<std::size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    for (int k = 0; k < 3; ++k) corners_[3 * fi + static_cast<std::size_t>(k)] = positions.row(faces(f, k)).transpose();
    centroids[fi] = (corners_[3 * fi] + corners_[3 * fi + 1] + corners_[3 * fi + 2]) / 3.0f;
    order_[fi] = static_cast<int>(f);
  }
  nodes_.reserve(static_cast<std::size_t>(2 * nf / kLeafSize + 1));
  if (nf > 0) build(0, static_cast<int>(nf), centroids);
}

int TriangleBvh::build(int begin, int end, std::vector<Eigen::Vector3f>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  Eigen::Vector3f clo = lo, chi = hi;
  for (int i = begin; i < end; ++i) {
    const auto f = static_cast<std::size_t>(order_[static_cast<std::size_t>(i)]);
    for (std::size_t k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(corners_[3 * f + k]);
      hi = hi.cwiseMax(corners_[3 * f + k]);
    }
    clo = clo.cwiseMin(centroids[f]);
    chi = chi.cwiseMax(centroids[f]);
  }
  nodes_[static_cast<std::size_t>(index)].lo = lo;
  nodes_[static_cast<std::size_t>(index)].hi = hi;
  if (end - begin <= kLeafSize) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
    return centroids[static_cast<std::size_t>(a)][axis] < centroids[static_cast<std::size_t>(b)][axis];
  });
  build(begin, mid, centroids);
  const int right = build(mid, end, centroids);
  nodes_[static_cast<std::size_t>(index)].first = right;
  return index;
}

template <class Overlaps, class Visit>
void TriangleBvh::traverse(Overlaps&& overlaps, Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
    if (!overlaps(node.lo, node.hi)) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) visit(order_[static_cast<std::size_t>(i)]);
    } else {
      stack[top++] = node.first;
      stack[top++] = static_cast<int>(&node - nodes_.data()) + 1;
    }
  }
}

void TriangleBvh::faces_near_plane(const Eigen::Vector3d& n, double d, double tolerance, std::vector<int>& out) const {
  traverse(
      [&](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
        const Eigen::Vector3d c = 0.5 * (lo + hi).cast<double>(), h = 0.5 * (hi - lo).cast<double>();
        return std::abs(n.dot(c) - d) <= n.cwiseAbs().dot(h) + tolerance;
      },
      [&](int f) { out.push_back(f); });
}

void TriangleBvh::faces_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const {
  traverse(
      [&](const Eigen::Vector3f& nlo, const Eigen::Vector3f& nhi) {
        return (nlo.cast<double>().array() <= hi.array()).all() && (nhi.cast<double>().array() >= lo.array()).all();
      },
      [&](int f) { out.push_back(f); });
}

std::vector<SegmentHit> TriangleBvh::segment_hits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  const Eigen::Vector3d dir = b - a;
  const Eigen::Vector3d slo = a.cwiseMin(b), shi = a.cwiseMax(b);
  std::vector<SegmentHit> hits;
  traverse(
      [&](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
        if ((lo.cast<double>().array() > shi.array()).any() || (hi.cast<double>().array() < slo.array()).any())
          return false;
        // Slab test of the segment against the box.
        double t0 = 0, t1 = 1;
        for (int k = 0; k < 3; ++k) {
          if (dir[k] == 0) continue;
          double ta = (lo[k] - a[k]) / dir[k], tb = (hi[k] - a[k]) / dir[k];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
        }
        return t0 <= t1 * (1 + 1e-12) + 1e-12;
      },
      [&](int f) {
        const auto fi = static_cast<std::size_t>(f);
        const Eigen::Vector3d p0 = corners_[3 * fi].cast<double>(), e1 = corners_[3 * fi + 1].cast<double>() - p0,
                              e2 = corners_[3 * fi + 2].cast<double>() - p0;
        const Eigen::Vector3d pv = dir.cross(e2);
        const double det = e1.dot(pv);
        if (std::abs(det) <= 1e-300) return;  // segment parallel to the face plane
        const Eigen::Vector3d tv = a - p0;
        const double u = tv.dot(pv) / det;
        const Eigen::Vector3d qv = tv.cross(e1);
        const double v = dir.dot(qv) / det;
        const double t = e2.dot(qv) / det;
        if (u < 0 || v < 0 || u + v > 1 || t < 0 || t > 1) return;
        hits.push_back({f, t, Eigen::Vector3d(1 - u - v, u, v)});
      });
  std::sort(hits.begin(), hits.end(), [](const SegmentHit& x, const SegmentHit& y) { return x.t < y.t; });
  return hits;
}

}  // namespace cgamesh::mesh
