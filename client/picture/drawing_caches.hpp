// SPDX-License-Identifier: MIT
// Cairo and fontconfig keep process-wide caches (fonts for the plot's text) that they never
// free by themselves, which leak checkers (ASan's LeakSanitizer) report at exit.
//
// Guarantees: after release_drawing_caches() those caches are freed; call it once, when no
// more drawing will happen in the process (end of `depath plot`, end of a test program).
#pragma once

namespace depath::picture {

void release_drawing_caches();

}  // namespace depath::picture
