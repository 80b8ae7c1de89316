#pragma once
// A row-major array of rows that keeps spare capacity, viewed as an Eigen matrix: the storage
// of every per-vertex and per-face array of a mesh.

#include <algorithm>
#include <cstddef>
#include <new>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::mesh {

/// The Eigen matrix a RowArray<T, Cols> views: #rows × Cols, row-major (a column vector for
/// Cols = 1, which Eigen stores column-major).
template <class T, int Cols>
using PlainRows = Eigen::Matrix<T, Eigen::Dynamic, Cols, Cols == 1 ? Eigen::ColMajor : Eigen::RowMajor>;

/// #rows × Cols values of T stored row after row, with spare capacity: growing it by a few rows
/// (the vertices and faces a cut adds to a million-face mesh) copies nothing until the capacity
/// is used up, which then grows by half, whereas an Eigen matrix reallocates (copies, unless the
/// allocator can remap) on every conservativeResize. Shrinking keeps the capacity.
///
/// It is an Eigen::Map over its own buffer, so rows, blocks, coefficients and expressions work as
/// on PlainRows<T, Cols> at the same speed; resize(), conservativeResize(), setZero(n, …),
/// setConstant(n, …) and assignment from an expression of any row count change the row count as
/// on a matrix, but all keep the rows that stay (resize() too). The view is re-made in place
/// whenever the buffer moves, as Eigen's own Ref re-makes its Map base.
template <class T, int Cols>
class RowArray : public Eigen::Map<PlainRows<T, Cols>> {
  static_assert(Cols >= 1, "a RowArray has a fixed, positive number of columns");

 public:
  using Base = Eigen::Map<PlainRows<T, Cols>>;

  RowArray() noexcept : Base(nullptr, 0, Cols) {}
  /// rows × cols zeros (cols must be Cols).
  RowArray(Eigen::Index rows, Eigen::Index cols) : RowArray() { resize(rows, cols); }
  /// A column of `size` values (Cols = 1).
  explicit RowArray(Eigen::Index size)
    requires(Cols == 1)
      : RowArray() {
    resize(size);
  }
  /// The values of any Eigen expression of Cols columns (implicit, as Eigen's matrices are).
  template <class Derived>
  RowArray(const Eigen::EigenBase<Derived>& other) : RowArray() {  // NOLINT(google-explicit-constructor)
    *this = other;
  }
  RowArray(const RowArray& other) : Base(nullptr, 0, Cols), buffer_(other.buffer_) { remap(); }
  RowArray(RowArray&& other) noexcept : Base(nullptr, 0, Cols), buffer_(std::move(other.buffer_)) {
    other.buffer_.clear();
    other.remap();
    remap();
  }
  RowArray& operator=(const RowArray& other) {
    if (this != &other) {
      buffer_ = other.buffer_;  // keeps this array's capacity when it suffices
      remap();
    }
    return *this;
  }
  RowArray& operator=(RowArray&& other) noexcept {
    if (this != &other) {
      buffer_ = std::move(other.buffer_);
      other.buffer_.clear();
      other.remap();
      remap();
    }
    return *this;
  }
  /// Takes the row count of `other`, then its values.
  template <class Derived>
  RowArray& operator=(const Eigen::EigenBase<Derived>& other) {
    resize(other.rows(), other.cols());
    Base::operator=(other.derived());
    return *this;
  }
  ~RowArray() = default;

  /// Sets the row count, keeping the first min(old, new) rows; new rows are zero.
  void resize(Eigen::Index rows, [[maybe_unused]] Eigen::Index cols) {
    eigen_assert(cols == Cols && "a RowArray's column count is fixed");
    set_rows(rows);
  }
  void resize(Eigen::Index rows, Eigen::NoChange_t) { set_rows(rows); }
  void resize(Eigen::Index size)
    requires(Cols == 1)
  {
    set_rows(size);
  }
  void conservativeResize(Eigen::Index rows, Eigen::Index cols) { resize(rows, cols); }
  void conservativeResize(Eigen::Index rows, Eigen::NoChange_t) { set_rows(rows); }
  void conservativeResize(Eigen::Index size)
    requires(Cols == 1)
  {
    set_rows(size);
  }

  using Base::setConstant;
  using Base::setOnes;
  using Base::setZero;
  RowArray& setZero(Eigen::Index rows, Eigen::Index cols) { return setConstant(rows, cols, T(0)); }
  RowArray& setZero(Eigen::Index size)
    requires(Cols == 1)
  {
    return setConstant(size, T(0));
  }
  RowArray& setConstant(Eigen::Index rows, Eigen::Index cols, const T& value) {
    resize(rows, cols);
    Base::setConstant(value);
    return *this;
  }
  RowArray& setConstant(Eigen::Index size, const T& value)
    requires(Cols == 1)
  {
    set_rows(size);
    Base::setConstant(value);
    return *this;
  }

  /// Makes room for `rows` rows in all without copying again.
  void reserve(Eigen::Index rows) { buffer_.reserve(static_cast<std::size_t>(rows) * Cols); remap(); }
  /// The rows it can hold without copying.
  [[nodiscard]] Eigen::Index capacity() const noexcept {
    return static_cast<Eigen::Index>(buffer_.capacity() / Cols);
  }

 private:
  void set_rows(Eigen::Index rows) {
    eigen_assert(rows >= 0);
    const std::size_t n = static_cast<std::size_t>(rows) * Cols;
    if (n > buffer_.capacity()) buffer_.reserve(std::max(n, buffer_.capacity() + buffer_.capacity() / 2));
    buffer_.resize(n);
    remap();
  }
  /// Re-makes the Map base over the buffer (a Map cannot be re-pointed otherwise).
  void remap() noexcept {
    ::new (static_cast<Base*>(this))
        Base(buffer_.empty() ? nullptr : buffer_.data(), static_cast<Eigen::Index>(buffer_.size() / Cols), Cols);
  }

  std::vector<T> buffer_;  ///< rows × Cols values; its size is always a whole number of rows
};

/// #rows × Cols floats (positions, normals, UVs, weights), row-major, with spare capacity.
template <int Cols>
using RowMatrixXf = RowArray<float, Cols>;
/// #F × 3 vertex indices of triangles.
using Faces = RowArray<int, 3>;

}  // namespace cgamesh::mesh
