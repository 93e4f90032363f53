#pragma once
// rostro's own default head, built procedurally: a stylised human head (skin, nose, cheeks,
// chin, brow ridge, eyebrows, lips around a real mouth opening, mouth interior, teeth,
// tongue, eyeballs with iris and pupil, eyelids that close over them) with its feature
// points, influence regions and rigid parts. Nothing third-party is shipped.

#include "facecore/face_model.hpp"

namespace rostro {

inline constexpr int kMinHeadVertices = 1500;

struct HeadOptions {
  int vertices = 5000;  // approximate total vertex count (>= kMinHeadVertices)
};

// Throws InputError when options.vertices is below the minimum.
FaceModel generate_head(const HeadOptions& options = {});

}  // namespace rostro
