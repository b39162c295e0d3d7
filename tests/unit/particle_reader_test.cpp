// Particle readers (io/particle_reader.h): known-content fixtures written by the tests, frames,
// element radii and colours, and malformed inputs -> InputError naming the line or byte.
#include "io/particle_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "core/error.h"
#include "io/dataset.h"
#include "io/particle_reader_elements.h"
#include "test_tmp.h"

namespace tc {
namespace {

std::string write(const std::string& name, const std::string& content) {
    std::string path = test::testDir() + "/" + name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
}

void expectError(const std::string& path, const std::string& where) {
    try {
        readParticles(path);
        ADD_FAILURE() << path << ": expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    }
}

TEST(ParticleReader, xyz_plain_and_extended_with_frames) {
    auto path = write("a.xyz", "2\nframe 0\nO 0 0 0\nH 0.96 0 0\n2\nframe 1\nO 0 0 1\nH 0.96 0 1\n");
    ParticleData d = readParticles(path);
    ASSERT_EQ(d.frameCount(), 2u);
    ASSERT_EQ(d.frames[1].size(), 2u);
    EXPECT_FLOAT_EQ(d.frames[1].positions[0].z, 1.0f);
    EXPECT_FLOAT_EQ(d.frames[0].radii[0], elementStyle("O").radius);
    EXPECT_FLOAT_EQ(d.frames[0].radii[1], 1.2f);
    EXPECT_EQ(glm::vec3(d.frames[0].colors[1]), glm::vec3(1.0f));  // hydrogen is white
    EXPECT_EQ(d.dataFrameFor(5), 1u);
    EXPECT_EQ(d.dataFrameFor(5, 0), 0u);

    auto ext =
        write("b.extxyz",
              "2\nLattice=\"1 0 0 0 1 0 0 0 1\" Properties=species:S:1:pos:R:3:radius:R:1:vel:R:3:energy:R:1 t=0\n"
              "C 1 2 3 0.5 1 0 0 -2.5\nN 4 5 6 0.25 0 1 0 -1.5\n");
    d = readParticles(ext);
    ASSERT_EQ(d.frames[0].size(), 2u);
    EXPECT_EQ(d.frames[0].positions[1], glm::vec3(4, 5, 6));
    EXPECT_FLOAT_EQ(d.frames[0].radii[1], 0.25f);
    ASSERT_NE(d.frames[0].attribute("energy"), nullptr);
    EXPECT_FLOAT_EQ(d.frames[0].attribute("energy")->values[1], -1.5f);
    ASSERT_NE(d.frames[0].attribute("vel_y"), nullptr);
    EXPECT_FLOAT_EQ(d.frames[0].attribute("vel_y")->values[1], 1.0f);

    expectError(write("c.xyz", "3\ncomment\nO 0 0 0\nH 1 x 0\nH 0 1 0\n"), "c.xyz:4:");
    expectError(write("d.xyz", "1000000000\ncomment\nO 0 0 0\n"), "d.xyz:1:");
    expectError(write("e.xyz", "2\ncomment\nO 0 0 0\n"), "unexpected end of file");
}

TEST(ParticleReader, pdb_models_are_frames_with_element_radii_and_cpk_colours) {
    const std::string atom1 = "ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00 10.00           N\n";
    const std::string atom2 = "ATOM      2  CA  ALA A   1      11.639   6.071  -5.147  1.00 12.50           C\n";
    const std::string het = "HETATM    3 FE   HEM A   2       1.000   2.000   3.000  0.50  5.00\n";
    auto path =
        write("p.pdb", "MODEL        1\n" + atom1 + atom2 + het + "ENDMDL\nMODEL        2\n" + atom1 + "ENDMDL\nEND\n");
    ParticleData d = readParticles(path);
    ASSERT_EQ(d.frameCount(), 2u);
    ASSERT_EQ(d.frames[0].size(), 3u);
    EXPECT_EQ(d.frames[1].size(), 1u);
    EXPECT_FLOAT_EQ(d.frames[0].positions[1].x, 11.639f);
    EXPECT_FLOAT_EQ(d.frames[0].radii[0], 1.55f);  // N
    EXPECT_FLOAT_EQ(d.frames[0].radii[1], 1.70f);  // CA of alanine is carbon (element column)
    EXPECT_FLOAT_EQ(d.frames[0].radii[2], 2.04f);  // FE from the HETATM name (no element column)
    EXPECT_FLOAT_EQ(d.frames[0].attribute("b_factor")->values[1], 12.5f);
    EXPECT_FLOAT_EQ(d.frames[0].attribute("occupancy")->values[2], 0.5f);
    expectError(write("bad.pdb", "ATOM      1  N   ALA A   1      11.104   6.1x4  -6.504  1.00 10.00           N\n"),
                "bad.pdb:1: expected a number for y (columns 39-46)");
}

TEST(ParticleReader, mmcif_atom_site_models_are_frames_like_pdb) {
    // Two models; a quoted atom name with a prime, a row split over two lines, '?' values.
    const std::string header =
        "data_TEST\n#\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n"
        "_atom_site.label_atom_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n"
        "_atom_site.occupancy\n_atom_site.B_iso_or_equiv\n_atom_site.auth_seq_id\n"
        "_atom_site.pdbx_PDB_model_num\n";
    const std::string rows =
        "ATOM 1 N N 11.104 6.134 -6.504 1.00 10.00 1 1\n"
        "ATOM 2 C \"C5'\" 11.639 6.071\n  -5.147 1.00 12.50 1 1\n"
        "HETATM 3 ? FE 1.0 2.0 3.0 0.5 ? . 1\n"
        "ATOM 1 N N 1 2 3 1 10 1 2\n#\n";
    auto path = write("m.cif", header + rows);
    ParticleData d = readParticles(path);
    ASSERT_EQ(d.frameCount(), 2u);
    ASSERT_EQ(d.frames[0].size(), 3u);
    EXPECT_EQ(d.frames[1].size(), 1u);
    EXPECT_FLOAT_EQ(d.frames[0].positions[1].z, -5.147f);
    EXPECT_FLOAT_EQ(d.frames[0].radii[0], 1.55f);                         // N
    EXPECT_FLOAT_EQ(d.frames[0].radii[1], 1.70f);                         // C (type_symbol)
    EXPECT_FLOAT_EQ(d.frames[0].radii[2], 2.04f);                         // FE from the HETATM atom name ('?' symbol)
    EXPECT_FLOAT_EQ(d.frames[0].attribute("b_factor")->values[2], 0.0f);  // '?' = missing
    EXPECT_TRUE(std::isnan(d.frames[0].attribute("residue")->values[2]));
    EXPECT_FLOAT_EQ(d.frames[1].positions[0].y, 2.0f);

    expectError(write("bad.cif", header + "ATOM 1 N N 11.1 6.x -6.5 1 1 1 1\n"),
                "bad.cif:15: expected a number for Cartn_y");
    expectError(write("short.cif", header + "ATOM 1 N N 11.1 6.1\n"),
                "short.cif:15: _atom_site loop ends inside a row (6 of 11 values)");
    expectError(write("none.cif", "data_X\n_cell.length_a 1\n"), "none.cif: no _atom_site loop");
}

TEST(ParticleReader, lammps_dump_scaled_and_unscaled_timesteps) {
    auto path = write("d.lammpstrj",
                      "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 10\n-5 5\n0 2\n"
                      "ITEM: ATOMS id type xs ys zs c_pe\n1 1 0.5 0.5 0.5 -3.2\n2 2 0.1 0.0 1.0 -1.0\n"
                      "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
                      "ITEM: ATOMS id type x y z radius\n1 1 1.5 2.5 3.5 0.3\n");
    ParticleData d = readParticles(path);
    ASSERT_EQ(d.frameCount(), 2u);
    EXPECT_EQ(d.frames[0].positions[0], glm::vec3(5.0f, 0.0f, 1.0f));
    EXPECT_EQ(d.frames[0].positions[1], glm::vec3(1.0f, -5.0f, 2.0f));
    EXPECT_FLOAT_EQ(d.frames[0].attribute("c_pe")->values[0], -3.2f);
    EXPECT_FLOAT_EQ(d.frames[0].attribute("type")->values[1], 2.0f);
    EXPECT_EQ(d.frames[1].positions[0], glm::vec3(1.5f, 2.5f, 3.5f));
    EXPECT_FLOAT_EQ(d.frames[1].radii[0], 0.3f);
    expectError(write("e.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n99999\nITEM: ATOMS x y z\n1 2 3\n"),
                "e.dump:");
    expectError(write("f.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x y\n1 2 3\n"),
                "f.dump:5: ITEM: ATOMS has no x y z");
}

TEST(ParticleReader, lammps_dump_time_item_is_the_frames_time) {
    // dump_modify time yes writes ITEM: TIME; the overlay's {time} shows it.
    auto path = write("t.lammpstrj",
                      "ITEM: TIMESTEP\n0\nITEM: TIME\n0.5\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x y z\n1 0 0 0\n"
                      "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x y z\n1 1 1 1\n");
    ParticleData d = readParticles(path);
    ASSERT_EQ(d.frameCount(), 2u);
    ASSERT_TRUE(d.frames[0].time);
    EXPECT_DOUBLE_EQ(*d.frames[0].time, 0.5);
    EXPECT_FALSE(d.frames[1].time);  // a frame without the item has no time
}

TEST(ParticleReader, gro_in_nm_becomes_angstrom_with_frames) {
    const std::string frame =
        "water\n    3\n    1SOL     OW    1   0.126   1.624   1.679\n"
        "    1SOL    HW1    2   0.190   1.661   1.747\n    1SOL    HW2    3   0.177   1.568   1.613\n"
        "   1.86206   1.86206   1.86206\n";
    ParticleData d = readParticles(write("w.gro", frame + frame));
    ASSERT_EQ(d.frameCount(), 2u);
    ASSERT_EQ(d.frames[0].size(), 3u);
    EXPECT_NEAR(d.frames[0].positions[0].x, 1.26f, 1e-5f);
    EXPECT_FLOAT_EQ(d.frames[0].radii[0], 1.52f);  // O
    EXPECT_FLOAT_EQ(d.frames[0].radii[1], 1.20f);  // H
    expectError(write("bad.gro", "t\n    2\n    1SOL     OW    1   0.126   1.624   1.679\n"), "bad.gro:");
}

// MMPLD writer for the fixtures: header, seek table, frames of lists (see particle_reader_mmpld.cpp).
struct Mmpld {
    std::string bytes;
    template <class T>
    void put(T v) {
        bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
};

std::string mmpldFile(std::uint16_t version, const std::vector<std::string>& frames) {
    Mmpld m;
    m.bytes.append("MMPLD\0", 6);
    m.put(version);
    m.put(std::uint32_t(frames.size()));
    for (int i = 0; i < 12; ++i) m.put(0.0f);
    std::uint64_t offset = m.bytes.size() + 8 * (frames.size() + 1);
    for (const auto& f : frames) {
        m.put(offset);
        offset += f.size();
    }
    m.put(offset);
    for (const auto& f : frames) m.bytes += f;
    return m.bytes;
}

TEST(ParticleReader, mmpld_versions_vertex_and_colour_types) {
    for (std::uint16_t version : {100, 101, 102, 103}) {
        Mmpld f;
        if (version >= 102) f.put(0.5f);  // timestamp
        f.put(std::int32_t(2));
        // List 0: float xyz with global radius 0.25, uint8 rgba colours.
        f.put(std::uint8_t(1));
        f.put(std::uint8_t(2));
        f.put(0.25f);
        f.put(std::uint64_t(2));
        if (version == 103)
            for (int i = 0; i < 6; ++i) f.put(0.0f);
        for (int i = 0; i < 2; ++i) {
            f.put(float(i));
            f.put(2.0f);
            f.put(3.0f);
            f.put(std::uint8_t(255));
            f.put(std::uint8_t(0));
            f.put(std::uint8_t(0));
            f.put(std::uint8_t(255));
        }
        if (version == 101) {
            f.put(std::uint32_t(0));
            f.put(std::uint64_t(0));
        }
        // List 1: float xyzr, float intensity with its range.
        f.put(std::uint8_t(2));
        f.put(std::uint8_t(3));
        f.put(0.0f);
        f.put(1.0f);
        f.put(std::uint64_t(1));
        if (version == 103)
            for (int i = 0; i < 6; ++i) f.put(0.0f);
        f.put(7.0f);
        f.put(8.0f);
        f.put(9.0f);
        f.put(0.75f);
        f.put(0.4f);
        if (version == 101) {
            f.put(std::uint32_t(0));
            f.put(std::uint64_t(0));
        }
        std::string file = mmpldFile(version, {f.bytes, f.bytes});
        auto path = write("v" + std::to_string(version) + ".mmpld", file);
        ParticleData d = readParticles(path);
        ASSERT_EQ(d.frameCount(), 2u) << version;
        ASSERT_EQ(d.frames[0].size(), 3u) << version;
        EXPECT_EQ(d.frames[0].positions[1], glm::vec3(1, 2, 3));
        EXPECT_FLOAT_EQ(d.frames[0].radii[0], 0.25f);
        EXPECT_FLOAT_EQ(d.frames[0].radii[2], 0.75f);
        EXPECT_EQ(d.frames[0].colors[0], glm::vec4(1, 0, 0, 1));
        EXPECT_FLOAT_EQ(d.frames[0].attribute("intensity")->values[2], 0.4f);
        EXPECT_FLOAT_EQ(d.frames[0].attribute("list")->values[2], 1.0f);
        // Truncated: the byte position is named.
        expectError(write("t" + std::to_string(version) + ".mmpld", file.substr(0, file.size() - 30)), ": byte ");
    }
    expectError(write("x.mmpld", mmpldFile(99, {})), "unsupported MMPLD version 99");
    // A particle count far beyond the file: refused before allocating.
    Mmpld huge;
    huge.put(std::int32_t(1));
    huge.put(std::uint8_t(1));
    huge.put(std::uint8_t(0));
    huge.put(0.1f);
    for (int i = 0; i < 4; ++i) huge.put(std::uint8_t(255));
    huge.put(std::uint64_t(1) << 60);
    expectError(write("h.mmpld", mmpldFile(100, {huge.bytes})), "exceed");
}

TEST(ParticleReader, dataset_dispatch_by_extension_and_droplets_generator) {
    auto path = write("a.xyz", "1\n\nC 1 2 3\n");
    DatasetSpec spec;
    spec.path = path;
    DatasetLoad load = loadDataset(spec);
    ASSERT_TRUE(load.isParticles());
    EXPECT_EQ(load.particles.frames[0].size(), 1u);
    DatasetSpec gen;
    gen.generate = "droplets";
    gen.particles = 500;
    load = loadDataset(gen);
    ASSERT_TRUE(load.isParticles());
    EXPECT_EQ(load.particles.frames[0].size(), 500u);
    EXPECT_NE(load.source.find("droplets"), std::string::npos);
}

}  // namespace
}  // namespace tc
