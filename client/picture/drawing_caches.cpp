// SPDX-License-Identifier: MIT
#include "picture/drawing_caches.hpp"

#include <cairo.h>
#include <fontconfig/fontconfig.h>

namespace depath::picture {

void release_drawing_caches() {
  cairo_debug_reset_static_data();
  FcFini();
}

}  // namespace depath::picture
