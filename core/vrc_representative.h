#pragma once
// Representative lines of the VRC LoD (Kanzler, Rautenhaus & Westermann 2019, Sect. 4): per level
// L of the Eq. 1 pyramid (voxels of 2^L x 2^L x 2^L model voxels) one straight line per voxel
// that stands for all line pieces inside it, for coarse rendering and for hard shadows against a
// chosen level (gl/vrc_renderer.h).
//
// Per level voxel, over the pieces whose axis lies in it (copies of core/vrc_model.h are skipped):
//   1. flip test: a piece is reversed when it points against the reference direction (that of
//      the heaviest piece), so lines crossing the voxel in opposite directions average instead of
//      cancelling;
//   2. weighted average of the start points and of the end points (weight = Eq. 1's length x
//      opacity of the piece; plain length where every piece is fully transparent), and of radius
//      and colour;
//   3. snapping: the line through the two averages is extended to the voxel's faces (entry and
//      exit of the voxel box), and with quantization q > 0 each end is moved to the centre of its
//      face bin (q x q bins per face, in absolute level-grid coordinates as the model's ends);
//   4. connection: where two face-neighbours' lines both end on their shared face within half a
//      level voxel of each other, both ends move to their midpoint (snapped again), so the
//      representative lines of a level form connected chains where the data do.
// A voxel without pieces has weight 0 (and a == b == its centre). A voxel whose pieces add up to
// less than 1/1000 of a model voxel in length (slivers at edges and corners) gets a point line
// a == b at their average, with faces kInteriorFace (no direction to extend along).
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/vrc_model.h"

namespace tc {

struct VrcRepresentativeLine {
    glm::vec3 a{0.0f}, b{0.0f};          // world space, on the level voxel's faces
    float radius = 0.0f;                 // weighted mean radius of the pieces
    float weight = 0.0f;                 // sum of the pieces' Eq. 1 weights (model voxel lengths)
    glm::vec4 color{0.0f};               // weighted mean colour, straight alpha
    std::uint32_t faceA = 0, faceB = 0;  // face ids of a and b (axis * 2 + side), as the model's codes;
                                         // kInteriorFace for a point line
};

struct VrcRepresentativeLevel {
    int level = 0;
    glm::ivec3 size{0};                        // ceil(model.size / 2^level)
    float voxelSize = 0.0f;                    // world units (model.voxelSize x 2^level)
    std::vector<VrcRepresentativeLine> lines;  // one per voxel, x fastest
    std::size_t index(glm::ivec3 v) const {
        return (std::size_t(v.z) * std::size_t(size.y) + std::size_t(v.y)) * std::size_t(size.x) + std::size_t(v.x);
    }
};

// Levels 0..maxLevel (clamped to the levels the grid has). oneTBB over level voxels; deterministic.
std::vector<VrcRepresentativeLevel> buildRepresentativeLines(const VrcModel& model, int maxLevel);

}  // namespace tc
