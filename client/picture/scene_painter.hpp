// SPDX-License-Identifier: MIT
// Paints a mesh and a path into a picture with Cairo: painter's-algorithm triangles with
// Lambert shading, the path on top, the endpoints as discs, an optional field overlay.
//
// Inputs: the mesh, the camera, the path's points (source first) and optionally one vector per
// vertex. Outputs: a PNG file of the camera's size. Guarantees: the colours below are exact
// at the endpoint discs' centres and on the path's line (tests read them back); errors writing
// the file throw Error(invalid_argument) naming it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "depath/mesh/mesh.hpp"
#include "picture/camera.hpp"

namespace depath::picture {

/// RGB in [0, 1].
using Colour = std::array<double, 3>;
inline constexpr Colour kPathColour{0.86, 0.08, 0.08};
inline constexpr Colour kSourceColour{0.05, 0.65, 0.15};
inline constexpr Colour kTargetColour{0.10, 0.25, 0.95};
inline constexpr Colour kBackgroundColour{1.0, 1.0, 1.0};

struct SceneStyle {
  /// Path line width and endpoint disc radius, pixels (0: from the picture size).
  double path_width = 0;
  double endpoint_radius = 0;
};

/// Draws the picture and writes it as PNG to `out`. `field` is empty or one vector per vertex.
void render_png(const Mesh& mesh, const OrthoCamera& camera, const std::vector<Vec3>& path,
                const std::vector<Vec3>& field, const std::string& out, const SceneStyle& style = {});

}  // namespace depath::picture
