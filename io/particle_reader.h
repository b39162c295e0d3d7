#pragma once
// Particle file readers, chosen by extension:
//   .xyz / .extxyz   XYZ: count line, comment line, "element x y z" rows; extended XYZ when the
//                    comment has Properties=name:type:cols:... (pos, radius, colour, any scalar);
//                    concatenated blocks are frames.
//   .pdb / .ent      PDB ATOM/HETATM records: element -> van der Waals radius (Angstrom) and CPK
//                    colour; MODEL/ENDMDL blocks are frames.
//   .cif / .mmcif    PDBx/mmCIF _atom_site loop, as PDB (pdbx_PDB_model_num = frames).
//   .lammpstrj / .dump  LAMMPS text dump: ITEM: TIMESTEP / NUMBER OF ATOMS / BOX BOUNDS / ATOMS
//                    with named columns (x y z, or scaled xs ys zs with the box); timesteps = frames.
//   .gro             GROMACS: nm converted to Angstrom; element radii from the atom name; frames.
//   .mmpld           MegaMol MMPLD versions 100-103: all vertex and colour types, lists, frames.
// Malformed input throws InputError naming the file and the line (text) or byte offset (binary);
// counts are checked against the file size before anything is allocated.
#include <string>

#include "core/particle_set.h"

namespace tc {

// True when the extension names a particle format above.
bool isParticleFile(const std::string& path);

ParticleData readParticles(const std::string& path);

}  // namespace tc
