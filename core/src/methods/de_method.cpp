// PLACEHOLDER until the DE helper replaces this file.
#include "methods/methods.hpp"
#include "depath/error.hpp"
namespace depath {
MethodOutcome run_de_method(const MethodContext&) { throw Error(ErrorCode::internal, "method de: not built yet"); }
}  // namespace depath
