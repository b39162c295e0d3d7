// `tubecast compare` (cli/compare.cpp) through the binary: the metrics it prints and its own exit
// code for --fail, distinct from 1 (internal error) and 2 (invalid input).
#include <gtest/gtest.h>

#include <string>

#include "cli_fixture.h"
#include "core/frame_images.h"
#include "io/image_io.h"

namespace {

using namespace tc::test;

class CompareCli : public CliFixture {
protected:
    // An opaque 8x6 grey image; `bright` pixels (from the first) are white instead.
    void writeImage(const std::string& name, int bright) {
        tc::FrameImages f;
        f.allocate(8, 6);
        for (int p = 0; p < 8 * 6; ++p) {
            const float v = p < bright ? 1.0f : 0.2f;
            for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = v;
            f.rgba[4 * p + 3] = 1.0f;
        }
        tc::writePng(f, (dir / name).string());
    }
};

TEST_F(CompareCli, fail_exits_6_only_when_the_psnr_is_below_the_threshold) {
    writeImage("a.png", 0);
    writeImage("b.png", 1);
    // One of 48 pixels differs by 131/255 in R, G and B (grey 0.2 is sRGB 124): RMSE over the
    // RGBA values = 0.514 * sqrt(3 / 192) = 0.064, PSNR 23.8 dB.
    RunResult below = run("compare a.png b.png --fail 30");
    EXPECT_EQ(below.code, 6) << below.err;
    EXPECT_NE(below.out.find("psnr 23.8"), std::string::npos) << below.out;  // the metrics still print
    RunResult above = run("compare a.png b.png --fail 20");
    EXPECT_EQ(above.code, 0) << above.err;
    RunResult same = run("compare a.png a.png --fail 100");
    EXPECT_EQ(same.code, 0) << same.err;
    EXPECT_NE(same.out.find("psnr inf"), std::string::npos) << same.out;
    RunResult missing = run("compare a.png nothing.png --fail 30");
    EXPECT_EQ(missing.code, 2);
    EXPECT_NE(missing.err.find("nothing.png"), std::string::npos) << missing.err;
}

TEST_F(CompareCli, help_lists_the_exit_code_of_fail) {
    RunResult r = run("compare --help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("Exit 6 if the PSNR"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("6  compare --fail"), std::string::npos) << r.out;
}

}  // namespace
