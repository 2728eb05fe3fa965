#include "tissue_trainer/core/model/tet_loops.h"

namespace tt {
namespace detail {

std::vector<Eigen::VectorXd>& forceBuffers(int count, Eigen::Index size) {
  thread_local std::vector<Eigen::VectorXd> buffers;
  if (static_cast<int>(buffers.size()) < count) buffers.resize(count);
  for (int b = 0; b < count; ++b)
    if (buffers[b].size() != size) buffers[b].resize(size);
  return buffers;
}

}  // namespace detail
}  // namespace tt
