// Registration of the fast culler family (src/cull/). Each algorithm lives in its own file.
#include "cullproof/methods.hpp"

namespace cullproof::detail {

void register_cull_methods(std::vector<Method>& out) {
  (void)out;
}

}  // namespace cullproof::detail
