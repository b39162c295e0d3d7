// dataset.trace (io/stream_tracer.h): streamlines of analytic fields written as VTK grids.
#include "io/stream_tracer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>

#include "core/error.h"
#include "test_tmp.h"

namespace tc {
namespace {

namespace fs = std::filesystem;

// A VTK XML ImageData (.vti, ASCII) on [-1, 1]^2 x [-0.1, 0.1] with spacing 0.1 holding the
// rigid rotation v = (-y, x, 0): as a 3-component array "velocity" and as scalars vx, vy, vz.
// Trilinear interpolation reproduces a linear field exactly, so the traced streamlines are
// circles about the z axis up to the integrator's error.
std::string writeRotationVti(const fs::path& dir) {
    std::ostringstream vec, vx, vy, vz;
    for (int k = 0; k <= 2; ++k)
        for (int j = 0; j <= 20; ++j)
            for (int i = 0; i <= 20; ++i) {
                double x = -1 + 0.1 * i, y = -1 + 0.1 * j;
                vec << -y << ' ' << x << " 0 ";
                vx << -y << ' ';
                vy << x << ' ';
                vz << "0 ";
            }
    std::string path = (dir / "rotation.vti").string();
    std::ofstream out(path);
    out << R"(<?xml version="1.0"?>
<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">
  <ImageData WholeExtent="0 20 0 20 0 2" Origin="-1 -1 -0.1" Spacing="0.1 0.1 0.1">
    <Piece Extent="0 20 0 20 0 2">
      <PointData Vectors="velocity">
        <DataArray type="Float64" Name="velocity" NumberOfComponents="3" format="ascii">)"
        << vec.str() << R"(</DataArray>
        <DataArray type="Float64" Name="vx" format="ascii">)"
        << vx.str() << R"(</DataArray>
        <DataArray type="Float64" Name="vy" format="ascii">)"
        << vy.str() << R"(</DataArray>
        <DataArray type="Float64" Name="vz" format="ascii">)"
        << vz.str() << R"(</DataArray>
      </PointData>
      <CellData></CellData>
    </Piece>
  </ImageData>
</VTKFile>
)";
    return path;
}

TraceSpec lineSeeds() {
    TraceSpec spec;
    spec.vector = "velocity";
    spec.seeding = TraceSpec::Seeding::Line;
    spec.seeds = 4;
    spec.lineFrom = {0.2f, 0.0f, 0.0f};
    spec.lineTo = {0.8f, 0.0f, 0.0f};
    spec.maxLength = 2.5f;  // per direction: half to three quarters of a turn at these radii
    return spec;
}

// Every vertex of every streamline stays on the circle through its seed (radii 0.2, 0.4, 0.6,
// 0.8), in the seed's plane.
void expectCircles(const LineSet& lines) {
    ASSERT_EQ(lines.polylineCount(), 4u);
    for (std::size_t p = 0; p < 4; ++p) {
        const double radius = 0.2 * double(p + 1);
        const std::uint32_t begin = lines.offsets[p], end = lines.offsets[p + 1];
        EXPECT_GT(end - begin, 8u) << "streamline " << p;
        double arc = 0;
        for (std::uint32_t v = begin; v < end; ++v) {
            const glm::vec3 x = lines.positions[v];
            EXPECT_NEAR(std::hypot(x.x, x.y), radius, 1e-4 * radius + 1e-5) << "streamline " << p << " vertex " << v;
            EXPECT_NEAR(x.z, 0.0f, 1e-6f);
            if (v > begin) arc += glm::length(x - lines.positions[v - 1]);
        }
        // Both directions, each up to max_length (or until the circle closes on the seed).
        EXPECT_GT(arc, std::min(2 * 2.5, 2 * std::numbers::pi * radius) * 0.95) << "streamline " << p;
    }
}

TEST(StreamTracer, RotationFieldStreamlinesAreCirclesOfTheirSeedRadius) {
    const std::string vti = writeRotationVti(test::testDir());
    CleanReport report;
    LineSet lines = traceStreamlines(vti, lineSeeds(), &report);
    expectCircles(lines);
    // The flow turns counter-clockwise: along each polyline the angle increases (one
    // polyline per seed, the backward half reversed in front of the forward half).
    const glm::vec3 a = lines.positions[lines.offsets[0]], b = lines.positions[lines.offsets[0] + 1];
    EXPECT_GT(a.x * b.y - a.y * b.x, 0.0f);
    // VTK's vorticity of v = (-y, x, 0) is (0, 0, 2); the speed of the field is the radius.
    const Attribute* vorticity = lines.attribute("Vorticity_z");
    const Attribute* speed = lines.attribute("velocity_magnitude");
    ASSERT_NE(vorticity, nullptr);
    ASSERT_NE(speed, nullptr);
    EXPECT_NEAR(vorticity->min, 2.0f, 1e-4f);
    EXPECT_NEAR(vorticity->max, 2.0f, 1e-4f);
    for (std::size_t v = 0; v < lines.vertexCount(); ++v)
        EXPECT_NEAR(speed->values[v], glm::length(glm::vec2(lines.positions[v])), 1e-4f);
}

TEST(StreamTracer, ThreeComponentArraysGiveTheSameStreamlines) {
    const std::string vti = writeRotationVti(test::testDir());
    TraceSpec spec = lineSeeds();
    spec.vector.clear();
    spec.components = {"vx", "vy", "vz"};
    LineSet lines = traceStreamlines(vti, spec);
    expectCircles(lines);
    // Assembled as "trace_vector", since the grid already has a "velocity" array.
    EXPECT_NE(lines.attribute("trace_vector_magnitude"), nullptr);
}

TEST(StreamTracer, ForwardOnlyStartsAtTheSeed) {
    const std::string vti = writeRotationVti(test::testDir());
    TraceSpec spec = lineSeeds();
    spec.direction = TraceSpec::Direction::Forward;
    LineSet lines = traceStreamlines(vti, spec);
    ASSERT_EQ(lines.polylineCount(), 4u);
    for (std::size_t p = 0; p < 4; ++p) {
        glm::vec3 first = lines.positions[lines.offsets[p]];
        EXPECT_NEAR(first.x, 0.2f * float(p + 1), 1e-6f);
        EXPECT_NEAR(first.y, 0.0f, 1e-6f);
    }
}

TEST(StreamTracer, RandomAndUniformSeedingAreDeterministicAndInsideTheGrid) {
    const std::string vti = writeRotationVti(test::testDir());
    TraceSpec spec = lineSeeds();
    spec.seeding = TraceSpec::Seeding::Uniform;
    spec.seeds = 16;
    spec.maxLength = 0.5f;
    LineSet uniform = traceStreamlines(vti, spec);
    EXPECT_GE(uniform.polylineCount(), 10u);
    spec.seeding = TraceSpec::Seeding::Random;
    LineSet a = traceStreamlines(vti, spec), b = traceStreamlines(vti, spec);
    EXPECT_EQ(a.positions, b.positions);
    for (const auto& x : a.positions) EXPECT_LE(std::max(std::abs(x.x), std::abs(x.y)), 1.0f + 1e-5f);
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

TEST(StreamTracer, ErrorsNameTheFileAndTheArray) {
    const std::string dir = test::testDir();
    const std::string vti = writeRotationVti(dir);
    TraceSpec spec = lineSeeds();
    spec.vector = "wind";
    EXPECT_EQ(errorOf([&] { traceStreamlines(vti, spec); }),
              vti +
                  ": dataset.trace.vector: no point array \"wind\" (available, with components: velocity (3), vx (1), "
                  "vy (1), vz (1))");
    spec.vector = "vx";
    EXPECT_EQ(errorOf([&] { traceStreamlines(vti, spec); }),
              vti + ": dataset.trace.vector: point array \"vx\" has 1 components, expected 3");
    EXPECT_EQ(errorOf([&] { traceStreamlines(dir + "/none.vti", lineSeeds()); }), dir + "/none.vti: no such file");
    std::ofstream(dir + "/broken.vti") << "<VTKFile type=\"ImageData\"";
    EXPECT_NE(errorOf([&] { traceStreamlines(dir + "/broken.vti", lineSeeds()); }).find(dir + "/broken.vti: VTK: "),
              std::string::npos);
    spec = lineSeeds();
    spec.lineFrom = {5, 5, 5};
    spec.lineTo = {6, 6, 6};
    EXPECT_EQ(
        errorOf([&] { traceStreamlines(vti, spec); }),
        vti + ": dataset.trace: no streamlines (4 seeds; seeds outside the grid or in zero velocity trace nothing)");
}

}  // namespace
}  // namespace tc
