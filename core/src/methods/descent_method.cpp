// PLACEHOLDER until the refinement helper replaces this file.
#include "methods/methods.hpp"
#include "depath/error.hpp"
namespace depath {
MethodOutcome run_descent_method(const MethodContext&) { throw Error(ErrorCode::internal, "method descent: not built yet"); }
}  // namespace depath
