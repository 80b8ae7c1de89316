#include "cgamesh/mesh/triangle_bvh.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cgamesh/errors.hpp"

namespace cgamesh::mesh {
namespace {

constexpr int kLeafSize = 4;

/// The segment a + t·dir, t ∈ [0, 1], set up once for many box tests: its own box, and the
/// reciprocals of its direction (a product per slab instead of a division). Scalar code on
/// purpose: Eigen's 3-vectors of doubles here compiled to 8-byte stores read back as 16-byte
/// loads, whose stalls perf put at a third of a query's time.
class Segment {
 public:
  Segment(const Eigen::Vector3d& a, const Eigen::Vector3d& dir) {
    for (int k = 0; k < 3; ++k) {
      a_[k] = a[k];
      lo_[k] = std::min(a[k], a[k] + dir[k]);
      hi_[k] = std::max(a[k], a[k] + dir[k]);
      inverse_[k] = 1 / dir[k];
    }
  }
  /// Whether the segment meets the box [lo − grow, hi + grow] (slab test, with a relative slack
  /// of 1e-12 for rounding).
  [[nodiscard]] bool meets(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, double grow) const {
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const double l = static_cast<double>(lo[k]) - grow, h = static_cast<double>(hi[k]) + grow;
      if (l > hi_[k] || h < lo_[k]) return false;
      // Along an axis the segment does not move, the test above is the whole slab test.
      if (!std::isfinite(inverse_[k])) continue;
      double ta = (l - a_[k]) * inverse_[k], tb = (h - a_[k]) * inverse_[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 <= t1 * (1 + 1e-12) + 1e-12;
  }

 private:
  double a_[3], lo_[3], hi_[3], inverse_[3];
};

/// @throws InvalidInputError when a corner is NaN or infinite.
void require_finite(const std::array<Eigen::Vector3f, 3>& corners) {
  if (!corners[0].allFinite() || !corners[1].allFinite() || !corners[2].allFinite())
    throw InvalidInputError("TriangleBvh: a placed corner is NaN or infinite");
}

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
  leaf_of_.resize(static_cast<std::size_t>(nf));
  slot_of_.resize(static_cast<std::size_t>(nf));
  next_appended_.assign(static_cast<std::size_t>(nf), -1);
  previous_appended_.assign(static_cast<std::size_t>(nf), -1);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    for (int k = 0; k < 3; ++k) corners_[3 * fi + static_cast<std::size_t>(k)] = positions.row(faces(f, k)).transpose();
    centroids[fi] = (corners_[3 * fi] + corners_[3 * fi + 1] + corners_[3 * fi + 2]) / 3.0f;
    order_[fi] = static_cast<int>(f);
  }
  nodes_.reserve(static_cast<std::size_t>(2 * nf / kLeafSize + 1));
  parent_.reserve(nodes_.capacity());
  if (nf > 0) build(0, static_cast<int>(nf), -1, centroids);
  first_appended_.assign(nodes_.size(), -1);
  slot_corners_.resize(corners_.size());
  for (std::size_t i = 0; i < order_.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k)
      slot_corners_[3 * i + k] = corners_[3 * static_cast<std::size_t>(order_[i]) + k];
}

int TriangleBvh::build(int begin, int end, int parent, std::vector<Eigen::Vector3f>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  parent_.push_back(parent);
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
    for (int i = begin; i < end; ++i) {
      const auto f = static_cast<std::size_t>(order_[static_cast<std::size_t>(i)]);
      leaf_of_[f] = index;
      slot_of_[f] = i;
    }
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
    return centroids[static_cast<std::size_t>(a)][axis] < centroids[static_cast<std::size_t>(b)][axis];
  });
  build(begin, mid, index, centroids);
  const int right = build(mid, end, index, centroids);
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
      for (int i = node.first; i < node.first + node.count; ++i)
        if (const int f = order_[static_cast<std::size_t>(i)]; f >= 0)
          visit(f, &slot_corners_[3 * static_cast<std::size_t>(i)]);
      for (int f = first_appended_[static_cast<std::size_t>(&node - nodes_.data())]; f >= 0;
           f = next_appended_[static_cast<std::size_t>(f)])
        visit(f, &corners_[3 * static_cast<std::size_t>(f)]);
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
      [&](int f, const Eigen::Vector3f* corners) {
        // The face itself, not only its leaf: some corner within the slab, or corners on both sides.
        double lo = INFINITY, hi = -INFINITY;
        for (std::size_t k = 0; k < 3; ++k) {
          const double x = n.dot(corners[k].cast<double>()) - d;
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
        if (lo <= tolerance && hi >= -tolerance) out.push_back(f);
      });
}

void TriangleBvh::faces_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const {
  traverse(
      [&](const Eigen::Vector3f& nlo, const Eigen::Vector3f& nhi) {
        return (nlo.cast<double>().array() <= hi.array()).all() && (nhi.cast<double>().array() >= lo.array()).all();
      },
      [&](int f, const Eigen::Vector3f*) { out.push_back(f); });
}

void TriangleBvh::faces_near_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
                                     std::vector<int>& out) const {
  const Eigen::Vector3d dir = b - a;
  const double length2 = dir.squaredNorm();
  const Segment segment(a, dir);
  // Within `radius` of the segment (Euclidean) implies meeting the box grown by `radius` (L∞):
  // the test of the nodes, and the first one of each face, then a sphere bound around its box.
  traverse([&](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) { return segment.meets(lo, hi, radius); },
           [&](int f, const Eigen::Vector3f* p) {
             const Eigen::Vector3f lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
             if (!segment.meets(lo, hi, radius)) return;
             double t = 0, half2 = 0;
             double c[3];
             for (int k = 0; k < 3; ++k) {
               c[k] = 0.5 * (static_cast<double>(lo[k]) + static_cast<double>(hi[k]));
               const double h = 0.5 * (static_cast<double>(hi[k]) - static_cast<double>(lo[k]));
               half2 += h * h;
               t += (c[k] - a[k]) * dir[k];
             }
             t = length2 > 0 ? std::clamp(t / length2, 0.0, 1.0) : 0.0;
             double d2 = 0;
             for (int k = 0; k < 3; ++k) {
               const double d = a[k] + t * dir[k] - c[k];
               d2 += d * d;
             }
             const double reach = radius + std::sqrt(half2);
             if (d2 <= reach * reach * (1 + 1e-12)) out.push_back(f);
           });
}

std::vector<SegmentHit> TriangleBvh::segment_hits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  const Eigen::Vector3d dir = b - a;
  const Segment segment(a, dir);
  std::vector<SegmentHit> hits;
  traverse([&](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) { return segment.meets(lo, hi, 0.0); },
           [&](int f, const Eigen::Vector3f* corners) {
             const Eigen::Vector3d p0 = corners[0].cast<double>(), e1 = corners[1].cast<double>() - p0,
                                   e2 = corners[2].cast<double>() - p0;
             const Eigen::Vector3d pv = dir.cross(e2);
             const double det = e1.dot(pv);
             if (std::abs(det) <= 1e-300) return;  // segment parallel to the face plane
             const Eigen::Vector3d tv = a - p0;
             const double u = tv.dot(pv) / det;
             const Eigen::Vector3d qv = tv.cross(e1);
             const double v = dir.dot(qv) / det;
             const double t = e2.dot(qv) / det;
             // A segment through a vertex or along an edge meets the faces there within rounding
             // (u or v a few ulps below 0): each of them counts as hit, at the clamped point.
             constexpr double eps = 1e-9;
             if (u < -eps || v < -eps || u + v > 1 + eps || t < -eps || t > 1 + eps) return;
             const double cu = std::clamp(u, 0.0, 1.0), cv = std::clamp(v, 0.0, 1.0 - cu);
             hits.push_back({f, std::clamp(t, 0.0, 1.0), Eigen::Vector3d(1 - cu - cv, cu, cv)});
           });
  std::sort(hits.begin(), hits.end(), [](const SegmentHit& x, const SegmentHit& y) { return x.t < y.t; });
  return hits;
}

// Face f has its slot_of_ entry already; its callers have checked the corners finite.
void TriangleBvh::set_corners(int f, const std::array<Eigen::Vector3f, 3>& corners) {
  const auto fi = static_cast<std::size_t>(f);
  for (std::size_t k = 0; k < 3; ++k) corners_[3 * fi + k] = corners[k];
  if (slot_of_[fi] >= 0)
    for (std::size_t k = 0; k < 3; ++k) slot_corners_[3 * static_cast<std::size_t>(slot_of_[fi]) + k] = corners[k];
}

void TriangleBvh::grow(int leaf, const std::array<Eigen::Vector3f, 3>& corners) {
  for (int n = leaf; n >= 0; n = parent_[static_cast<std::size_t>(n)]) {
    Node& node = nodes_[static_cast<std::size_t>(n)];
    const auto inside = [&](const Eigen::Vector3f& p) {
      return (p.array() >= node.lo.array()).all() && (p.array() <= node.hi.array()).all();
    };
    if (std::all_of(corners.begin(), corners.end(), inside)) return;  // so are its ancestors'
    for (const auto& p : corners) {
      node.lo = node.lo.cwiseMin(p);
      node.hi = node.hi.cwiseMax(p);
    }
  }
}

void TriangleBvh::reserve(int faces) {
  const auto n = static_cast<std::size_t>(std::max(faces, 0));
  corners_.reserve(3 * n);
  leaf_of_.reserve(n);
  slot_of_.reserve(n);
  next_appended_.reserve(n);
  previous_appended_.reserve(n);
}

void TriangleBvh::replace(int f, const std::array<Eigen::Vector3f, 3>& corners) {
  if (f < 0 || f >= face_count()) throw InvalidInputError("TriangleBvh: no face " + std::to_string(f) + " to replace");
  require_finite(corners);
  set_corners(f, corners);
  grow(leaf_of_[static_cast<std::size_t>(f)], corners);
}

void TriangleBvh::append(const std::array<Eigen::Vector3f, 3>& corners, int near) {
  if (near < 0 || near >= face_count())
    throw InvalidInputError("TriangleBvh: no face " + std::to_string(near) + " to append next to");
  require_finite(corners);  // before any array grows: a throw leaves the tree as it was
  const int f = face_count(), leaf = leaf_of_[static_cast<std::size_t>(near)];
  corners_.resize(corners_.size() + 3);
  leaf_of_.push_back(leaf);
  slot_of_.push_back(-1);
  set_corners(f, corners);
  // At the front of the leaf's list.
  int& first = first_appended_[static_cast<std::size_t>(leaf)];
  next_appended_.push_back(first);
  previous_appended_.push_back(-1);
  if (first >= 0) previous_appended_[static_cast<std::size_t>(first)] = f;
  first = f;
  grow(leaf, corners);
}

void TriangleBvh::link_appended(int f, int previous, int next) {
  if (previous >= 0)
    next_appended_[static_cast<std::size_t>(previous)] = f;
  else
    first_appended_[static_cast<std::size_t>(leaf_of_[static_cast<std::size_t>(f)])] = f;
  if (next >= 0) previous_appended_[static_cast<std::size_t>(next)] = f;
}

void TriangleBvh::erase(int f) {
  if (f < 0 || f >= face_count()) throw InvalidInputError("TriangleBvh: no face " + std::to_string(f) + " to erase");
  const auto fi = static_cast<std::size_t>(f);
  // Take f out of its leaf (whose box stays: larger than needed, never too small).
  if (const int slot = slot_of_[fi]; slot >= 0) {
    order_[static_cast<std::size_t>(slot)] = -1;
  } else {
    const int previous = previous_appended_[fi], next = next_appended_[fi];
    if (previous >= 0)
      next_appended_[static_cast<std::size_t>(previous)] = next;
    else
      first_appended_[static_cast<std::size_t>(leaf_of_[fi])] = next;
    if (next >= 0) previous_appended_[static_cast<std::size_t>(next)] = previous;
  }
  // The last face takes id f.
  const int last = face_count() - 1;
  if (f != last) {
    const auto li = static_cast<std::size_t>(last);
    leaf_of_[fi] = leaf_of_[li];
    slot_of_[fi] = slot_of_[li];
    next_appended_[fi] = next_appended_[li];
    previous_appended_[fi] = previous_appended_[li];
    if (slot_of_[fi] >= 0)
      order_[static_cast<std::size_t>(slot_of_[fi])] = f;
    else
      link_appended(f, previous_appended_[fi], next_appended_[fi]);
    for (std::size_t k = 0; k < 3; ++k) corners_[3 * fi + k] = corners_[3 * li + k];
  }
  corners_.resize(corners_.size() - 3);
  leaf_of_.pop_back();
  slot_of_.pop_back();
  next_appended_.pop_back();
  previous_appended_.pop_back();
}

}  // namespace cgamesh::mesh
