#include "hoidslam/bow/bow_vector.h"

#include <algorithm>

namespace hoidslam::bow {

double Score(const BowVector& a, const BowVector& b) {
  double shared = 0.0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->word < ib->word) {
      ++ia;
    } else if (ib->word < ia->word) {
      ++ib;
    } else {
      shared += std::min(ia->weight, ib->weight);
      ++ia;
      ++ib;
    }
  }
  // Rounding may carry the sum of a vector's weights a hair past 1.
  return std::min(shared, 1.0);
}

}  // namespace hoidslam::bow
