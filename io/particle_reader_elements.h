#pragma once
// Chemical elements for particle readers (PDB, GRO, XYZ): van der Waals radii in Angstrom
// (Bondi 1964; Alvarez 2013 for elements Bondi lacks) and CPK colours as Jmol draws them (sRGB).
#include <glm/glm.hpp>
#include <string>

namespace tc {

struct ElementStyle {
    float radius;     // Angstrom
    glm::vec3 color;  // sRGB
};

// Case-insensitive symbol ("C", "cl", "FE"). Unknown symbols get radius 1.7 A (carbon) and Jmol's
// pink for unknown elements; `known` says which it was.
ElementStyle elementStyle(const std::string& symbol, bool* known = nullptr);

// The element of an atom name as PDB/GRO files write it when no element column is given: leading
// digits skipped, then one or two letters ("CA" in a protein is the alpha carbon: names are
// matched to single-letter elements first, except for a few ions written as their symbol: CL,
// NA, MG, ZN, FE, CA only when the whole name is that symbol and `ionHint`).
std::string elementFromAtomName(const std::string& name, bool ionHint);

}  // namespace tc
