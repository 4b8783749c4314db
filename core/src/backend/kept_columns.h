// A matrix whose column count changes from call to call (one column per point of the window)
// kept in one buffer, so that its memory stays instead of being allocated each time.
#pragma once

#include <Eigen/Core>

namespace ldsm {

/// The first `cols` columns of `buffer`, a `rows` x `cols` view. The buffer is reallocated (a
/// quarter more columns than asked, contents undefined) only when its row count differs or it has
/// too few columns.
inline Eigen::MatrixXd::ColsBlockXpr keptColumns(Eigen::MatrixXd& buffer, Eigen::Index rows,
                                                 Eigen::Index cols) {
  if (buffer.rows() != rows || buffer.cols() < cols) buffer.resize(rows, cols + cols / 4);
  return buffer.leftCols(cols);
}

}  // namespace ldsm
