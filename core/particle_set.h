#pragma once
// Particle data: points with an optional per-particle radius and colour and any number of
// scalar attributes, one frame or a time series of frames. What particle readers and the
// droplets generator produce and particle styling (core/particle_styling.h) consumes.
#include <cstddef>
#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/line_set.h"

namespace tc {

// Where a frame's radii or colours come from: a column or array of the file, or the chemical
// element of each atom (van der Waals radii, CPK colours). Both lose to an explicit style entry;
// docs/scene-spec.md "Precedence".
enum class Provenance { None, File, Elements };

// One time step. Every per-particle array is either empty or has positions.size() entries.
struct ParticleSet {
    std::vector<glm::vec3> positions;  // finite
    // Radii the data carries (PDB/GRO element radii, MMPLD per-particle radii, a "radius" column),
    // in world units; empty when the data has none and style.radius decides.
    std::vector<float> radii;
    // Colours the data carries (PDB CPK colours, MMPLD colours), sRGB in [0, 1] with straight
    // alpha; empty when the data has none and style.color decides.
    std::vector<glm::vec4> colors;
    Provenance radiiFrom = Provenance::None, colorsFrom = Provenance::None;
    std::map<std::string, float> elementRadii;  // Provenance::Elements: each element's radius
    std::vector<Attribute> attributes;          // one value per particle
    Bounds bounds;                              // of the positions (radii are added by styling)
    std::optional<double> time;                 // the simulation time the file states (LAMMPS "ITEM: TIME")

    std::size_t size() const { return positions.size(); }
    const Attribute* attribute(const std::string& name) const;
    // Recomputes bounds and attribute ranges.
    void update();
    // Throws tc::Error(Internal) if an array's size does not match positions (a reader bug).
    void checkConsistent() const;
};

// ParticleData::dataFrameFor of a series of `frameCount` data frames.
std::size_t dataFrameFor(std::size_t frameCount, int frame, int pinned);

// A particle dataset: one frame, or a time series (LAMMPS dumps, MMPLD, multi-model PDB, ...).
// Frames may differ in particle count.
struct ParticleData {
    std::vector<ParticleSet> frames;

    std::size_t frameCount() const { return frames.size(); }
    // The data frame shown at animation frame `frame` (Sect. "Time series" of docs/scene-spec.md):
    // `pinned` >= 0 selects that data frame (clamped to the last), otherwise min(frame, last).
    std::size_t dataFrameFor(int frame, int pinned = -1) const;
    // Union of the frames' bounds.
    Bounds bounds() const;
    std::size_t maxParticles() const;
};

}  // namespace tc
