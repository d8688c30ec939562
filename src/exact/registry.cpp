// Registration of Hoff's test and the exact float tests (src/exact/).
#include "cullproof/methods.hpp"

namespace cullproof::detail {

void register_exact_methods(std::vector<Method>& out) {
  (void)out;
}

}  // namespace cullproof::detail
