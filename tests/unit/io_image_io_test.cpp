#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <utility>

#include "core/color.h"
#include "core/compositing.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/image_io.h"
#include "test_tmp.h"

namespace fs = std::filesystem;

namespace tc {
namespace {

using tc::test::testDir;  // a fresh directory per test (test_tmp.h)

std::vector<std::string> filesIn(const std::string& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

void setPixel(FrameImages& f, int x, int y, float r, float g, float b, float a) {
    float* p = &f.rgba[4 * (std::size_t(y) * std::size_t(f.width) + std::size_t(x))];
    p[0] = r, p[1] = g, p[2] = b, p[3] = a;
}

TEST(WritePng, premultiplied_linear_becomes_straight_srgb_8bit) {
    FrameImages f;
    f.allocate(3, 1);
    // Straight linear colours chosen as exact sRGB codes 200 and 128, premultiplied by 0.6.
    const float r = srgbToLinear(200.0f / 255.0f), g = srgbToLinear(128.0f / 255.0f);
    setPixel(f, 0, 0, 0.6f * r, 0.6f * g, 0.0f, 0.6f);
    setPixel(f, 1, 0, 0.0f, 0.0f, 0.0f, 0.0f);   // background
    setPixel(f, 2, 0, 1.0f, 2.0f, -1.0f, 1.0f);  // out of range: clamped
    std::string path = testDir() + "/frame.png";
    writePng(f, path);

    RgbaImage img = readImageRgba(path);
    ASSERT_EQ(img.width, 3);
    ASSERT_EQ(img.height, 1);
    std::vector<int> bytes;
    for (float v : img.rgba) bytes.push_back(int(std::lround(v * 255.0f)));
    EXPECT_EQ(bytes, (std::vector<int>{200, 128, 0, 153, 0, 0, 0, 0, 255, 255, 0, 255}));
}

TEST(WritePng, told_opaque_writes_the_bytes_of_the_scan_for_frames_composited_over_an_opaque_background) {
    // The frame loop's premise (cli/frame_loop.cpp): over an opaque background every alpha rounds
    // to 255, whatever the technique's alpha in [0, 1], so the scan would pick RGB too.
    std::mt19937 rng(7u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FrameImages f;
    f.allocate(61, 17);
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const float a = (x + y) % 5 == 0 ? 0.0f : (x + y) % 5 == 1 ? 1.0f : u(rng);
            setPixel(f, x, y, a * u(rng), a * u(rng), a * u(rng), a);
        }
    compositeUnder(f, {0.2f, 0.4f, 0.9f, 1.0f});
    const std::string scanned = testDir() + "/scanned.png", told = testDir() + "/told.png";
    writePng(f, scanned);
    writePng(f, told, {}, kPngFrameZlibLevel, PngAlpha::Opaque);
    std::ifstream a(scanned, std::ios::binary), b(told, std::ios::binary);
    const std::string bytesA((std::istreambuf_iterator<char>(a)), {}), bytesB((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(bytesA.empty());
    EXPECT_EQ(bytesA, bytesB);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(told);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().nchannels, 3);
}

TEST(WritePng, half_alpha_example_from_the_spec) {
    // rgb 0.5 * 0.214 with alpha 0.5: straight linear 0.214 -> sRGB 0.49996 -> 127.49 -> 127.
    FrameImages f;
    f.allocate(1, 1);
    setPixel(f, 0, 0, 0.5f * 0.214f, 0.5f * 0.214f, 0.5f * 0.214f, 0.5f);
    std::string path = testDir() + "/half.png";
    writePng(f, path);
    RgbaImage img = readImageRgba(path);
    EXPECT_EQ(std::lround(img.rgba[0] * 255.0f), 127);
    EXPECT_EQ(std::lround(img.rgba[3] * 255.0f), 128);  // 127.5 rounds away from zero
}

TEST(WritePng, opaque_frames_are_rgb_with_the_same_pixels_and_any_transparency_keeps_alpha) {
    FrameImages f;
    f.allocate(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) setPixel(f, x, y, 0.1f * float(x), 0.3f * float(y), 0.7f, 1.0f);
    const std::string rgbPath = testDir() + "/opaque.png";
    writePng(f, rgbPath);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(rgbPath);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().nchannels, 3);
    in->close();
    const RgbaImage rgb = readImageRgba(rgbPath);

    // The same colours with one pixel at alpha 254/255 (premultiplied): RGBA, every other pixel
    // decodes to the same bytes.
    FrameImages g = f;
    const float a = 254.0f / 255.0f;
    setPixel(g, 3, 1, 0.3f * a, 0.3f * a, 0.7f * a, a);
    const std::string rgbaPath = testDir() + "/alpha.png";
    writePng(g, rgbaPath);
    in = OIIO::ImageInput::open(rgbaPath);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().nchannels, 4);
    in->close();
    const RgbaImage rgba = readImageRgba(rgbaPath);
    ASSERT_EQ(rgb.rgba.size(), rgba.rgba.size());
    for (std::size_t i = 0; i + 4 < rgb.rgba.size(); ++i) EXPECT_EQ(rgb.rgba[i], rgba.rgba[i]) << "channel " << i;
    EXPECT_EQ(rgb.rgba.back(), 1.0f);
    EXPECT_NEAR(rgba.rgba.back(), a, 1e-6f);

    // The decision is by the 8-bit code of alpha: 0.999 x 255 = 254.7 stores as 255 (RGB),
    // 0.998 x 255 = 254.49 as 254 (RGBA).
    for (auto [alpha, channels] : {std::pair{0.999f, 3}, std::pair{0.998f, 4}}) {
        FrameImages h = f;
        setPixel(h, 0, 0, 0.1f * alpha, 0.2f * alpha, 0.3f * alpha, alpha);
        const std::string path = testDir() + "/threshold.png";
        writePng(h, path);
        in = OIIO::ImageInput::open(path);
        ASSERT_TRUE(in);
        EXPECT_EQ(in->spec().nchannels, channels) << alpha;
        in->close();
    }
}

TEST(WritePng, runs_of_equal_pixels_encode_as_each_pixel_alone) {
    // writePng reuses a pixel's bytes for the next pixel with the same floats. Each pixel here,
    // written alone as a 1x1 image, is the reference: runs, neighbours that differ in one channel
    // only (each of the four in turn), +0 against -0 (other bits, same code), NaN, alpha 0 and
    // partial alpha, runs across rows.
    const float a = 0.37f, c = 0.25f;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::array<float, 4>> pixels = {
        {c, c, c, 1.0f},
        {c, c, c, 1.0f},
        {0.8f, c, c, 1.0f},
        {0.8f, 0.8f, c, 1.0f},
        {0.8f, 0.8f, 0.8f, 1.0f},
        {0.8f, 0.8f, 0.8f, 0.9f},
        {0.0f, 0.0f, 0.0f, 0.0f},
        {-0.0f, 0.0f, 0.0f, 0.0f},
        {a * 0.5f, a * 0.2f, a, a},
        {a * 0.5f, a * 0.2f, a, a},
        {nan, c, c, 1.0f},
        {nan, c, c, 1.0f},
        {nan, c, c, 1.0f},
    };
    FrameImages f;
    f.allocate(4, 4);  // the last three pixels stay background
    for (std::size_t i = 0; i < pixels.size(); ++i)
        setPixel(f, int(i % 4), int(i / 4), pixels[i][0], pixels[i][1], pixels[i][2], pixels[i][3]);
    const std::string dir = testDir();
    writePng(f, dir + "/runs.png");
    const RgbaImage runs = readImageRgba(dir + "/runs.png");
    ASSERT_EQ(runs.rgba.size(), 4u * 16u);
    for (std::size_t i = 0; i < 16; ++i) {
        FrameImages one;
        one.allocate(1, 1);
        const float* p = &f.rgba[4 * i];
        setPixel(one, 0, 0, p[0], p[1], p[2], p[3]);
        writePng(one, dir + "/one.png");
        const RgbaImage alone = readImageRgba(dir + "/one.png");
        for (std::size_t k = 0; k < 4; ++k)
            EXPECT_EQ(runs.rgba[4 * i + k], alone.rgba[k]) << "pixel " << i << " channel " << k;
    }
}

TEST(WritePng, leaves_no_temp_file_and_replaces_the_previous_one) {
    std::string dir = testDir();
    std::string path = dir + "/frame.0001.png";
    std::ofstream(path) << "old";
    FrameImages f;
    f.allocate(2, 2);
    writePng(f, path);
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"frame.0001.png"});
    EXPECT_EQ(readImageRgba(path).width, 2);
}

TEST(WritePng, unwritable_destination_throws_output_error_naming_the_path) {
    std::string path = testDir() + "/no/such/dir/frame.png";
    FrameImages f;
    f.allocate(2, 2);
    try {
        writePng(f, path);
        FAIL() << "no OutputError";
    } catch (const OutputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": cannot write PNG: ", 0), 0u) << e.what();
    }
}

TEST(AtomicFile, temp_name_sits_next_to_the_final_file_and_keeps_the_extension) {
    AtomicFile file("out/frame.0001.png");
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    EXPECT_EQ(file.tempPath(),
              "out/.frame.0001.png.tmp-" + std::string(host) + "-" + std::to_string(getpid()) + ".png");
}

TEST(AtomicFile, throwing_before_commit_keeps_the_previous_file_and_removes_the_temp) {
    std::string dir = testDir();
    std::string path = dir + "/data.json";
    std::ofstream(path) << "previous";
    try {
        AtomicFile file(path);
        std::ofstream(file.tempPath()) << "half written";
        throw std::runtime_error("writer failed");
    } catch (const std::runtime_error&) {
    }
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"data.json"});
    std::ifstream in(path);
    std::string content((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(content, "previous");
}

TEST(AtomicFile, commit_onto_a_directory_fails_and_cleans_up) {
    std::string dir = testDir();
    fs::create_directories(dir + "/taken/inside");
    FrameImages f;
    f.allocate(1, 1);
    EXPECT_THROW(writePng(f, dir + "/taken"), OutputError);
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"taken"});
}

TEST(EnsureWritableDir, creates_nested_directories) {
    std::string dir = testDir() + "/a/b/c";
    ensureWritableDir(dir);
    EXPECT_TRUE(fs::is_directory(dir));
    ensureWritableDir(dir);  // existing is fine
}

TEST(EnsureWritableDir, a_file_in_the_way_is_reported) {
    std::string base = testDir();
    std::ofstream(base + "/file") << "x";
    std::string dir = base + "/file/sub";
    try {
        ensureWritableDir(dir);
        FAIL() << "no OutputError";
    } catch (const OutputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(dir + ": cannot create output directory: ", 0), 0u) << e.what();
    }
}

TEST(EnsureWritableDir, read_only_directory_is_not_writable) {
    if (geteuid() == 0) GTEST_SKIP() << "root can write anywhere";
    std::string dir = testDir() + "/ro";
    fs::create_directories(dir);
    fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_THROW(ensureWritableDir(dir), OutputError);
    fs::permissions(dir, fs::perms::owner_all);
}

FrameImages makeFrame() {
    FrameImages f;
    f.allocate(3, 2);
    for (std::size_t i = 0; i < f.pixelCount(); ++i) {
        float t = float(i) / 5.0f;
        setPixel(f, int(i % 3), int(i / 3), 0.1f + t * 0.3f, 0.7f * t, 1.5f * t, t);
        f.depth[i] = 2.5f + 0.123456f * float(i);
        f.normal[3 * i + 0] = 0.6f;
        f.normal[3 * i + 1] = -0.8f * t;
        f.normal[3 * i + 2] = 0.0123456789f;
        f.id[i] = std::uint32_t(i) * 1000u;
    }
    f.depth[0] = std::numeric_limits<float>::infinity();
    f.id[0] = kBackgroundId;
    f.id[1] = 16777217u;  // 2^24 + 1: not representable as float
    f.id[2] = 0xFFFFFFFEu;
    f.ao.assign(f.pixelCount(), 0.25f);
    f.ao[3] = 0.9f;
    return f;
}

TEST(WriteExr, round_trip_of_all_channels) {
    FrameImages f = makeFrame();
    ExrOptions options;
    options.ao = true;
    options.metadata = {{"tubecast:scene", "tornado.json"}, {"tubecast:technique", "kbuffer"}};
    std::string dir = testDir();
    std::string path = dir + "/frame.exr";
    writeExr(f, path, options);
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"frame.exr"});

    std::map<std::string, std::string> metadata;
    FrameImages back = readExr(path, &metadata);
    ASSERT_EQ(back.width, 3);
    ASSERT_EQ(back.height, 2);
    // RGBA and AO are HALF: 11-bit significand, relative error <= 2^-11.
    ASSERT_EQ(back.rgba.size(), f.rgba.size());
    for (std::size_t i = 0; i < f.rgba.size(); ++i)
        EXPECT_NEAR(back.rgba[i], f.rgba[i], std::abs(f.rgba[i]) * 0x1p-11f + 1e-7f) << i;
    ASSERT_EQ(back.ao.size(), f.ao.size());
    for (std::size_t i = 0; i < f.ao.size(); ++i) EXPECT_NEAR(back.ao[i], f.ao[i], f.ao[i] * 0x1p-11f);
    // Z and N are FLOAT: exact, including +inf on the background.
    EXPECT_EQ(back.depth, f.depth);
    EXPECT_TRUE(std::isinf(back.depth[0]) && back.depth[0] > 0);
    EXPECT_EQ(back.normal, f.normal);
    // id is UINT: exact.
    EXPECT_EQ(back.id, f.id);
    EXPECT_EQ(metadata["tubecast:scene"], "tornado.json");
    EXPECT_EQ(metadata["tubecast:technique"], "kbuffer");
}

TEST(WriteExr, optional_channels_can_be_left_out) {
    FrameImages f = makeFrame();
    ExrOptions options;
    options.depth = options.normal = options.id = false;
    options.ao = true;
    f.ao.clear();  // requested but not rendered: not written
    std::string path = testDir() + "/rgba.exr";
    writeExr(f, path, options);
    FrameImages back = readExr(path);
    EXPECT_EQ(back.rgba.size(), f.rgba.size());
    EXPECT_TRUE(back.depth.empty());
    EXPECT_TRUE(back.normal.empty());
    EXPECT_TRUE(back.id.empty());
    EXPECT_TRUE(back.ao.empty());
}

TEST(ReadExr, missing_file) {
    std::string path = testDir() + "/nope.exr";
    try {
        readExr(path);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": no such file");
    }
}

TEST(ReadImageRgba, garbage_names_the_file) {
    std::string path = testDir() + "/bad.png";
    std::ofstream(path) << "not a png";
    try {
        readImageRgba(path);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": cannot read image: ", 0), 0u) << e.what();
    }
}

std::string writeRgbaExr(const std::string& path, int w, int h, float value, float offset = 0.0f,
                         int offsetColumns = 0) {
    FrameImages f;
    f.allocate(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float d = x < offsetColumns ? offset : 0.0f;
            setPixel(f, x, y, value + d, value + d, value, value);
        }
    ExrOptions options;
    options.depth = options.normal = options.id = false;
    writeExr(f, path, options);
    return path;
}

TEST(CompareImages, identical_images_have_zero_error_and_infinite_psnr) {
    std::string dir = testDir();
    FrameImages f = makeFrame();
    writePng(f, dir + "/a.png");
    writePng(f, dir + "/b.png");
    ImageDiff d = compareImages(dir + "/a.png", dir + "/b.png", 0.0f);
    EXPECT_EQ(d.rmse, 0.0);
    EXPECT_EQ(d.maxError, 0.0);
    EXPECT_TRUE(std::isinf(d.psnr));
    EXPECT_EQ(d.fractionOver, 0.0);
    EXPECT_EQ(d.pixels, 6u);
}

TEST(CompareImages, known_offset_gives_expected_rmse_and_psnr) {
    std::string dir = testDir();
    // 4x2 image; in the left 2 columns R and G are 0.25 higher (exact in half): 8 of 32 values
    // differ by 0.25 -> RMSE = sqrt(8 * 0.0625 / 32) = 0.125, PSNR = 20 log10(8) = 18.0618 dB,
    // and half of the pixels exceed a 0.1 threshold.
    std::string a = writeRgbaExr(dir + "/a.exr", 4, 2, 0.5f);
    std::string b = writeRgbaExr(dir + "/b.exr", 4, 2, 0.5f, 0.25f, 2);
    ImageDiff d = compareImages(a, b, 0.1f);
    EXPECT_NEAR(d.rmse, 0.125, 1e-9);
    EXPECT_NEAR(d.psnr, 20.0 * std::log10(8.0), 1e-6);
    EXPECT_NEAR(d.maxError, 0.25, 1e-9);
    EXPECT_DOUBLE_EQ(d.fractionOver, 0.5);
    EXPECT_EQ(d.pixels, 8u);
    EXPECT_EQ(compareImages(a, b, 0.3f).fractionOver, 0.0);
}

TEST(CompareImages, different_sizes_name_both) {
    std::string dir = testDir();
    std::string a = writeRgbaExr(dir + "/a.exr", 4, 2, 0.5f);
    std::string b = writeRgbaExr(dir + "/b.exr", 3, 2, 0.5f);
    try {
        compareImages(a, b, 0.0f);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), a + ": image size 4x2 differs from " + b + ": 3x2");
    }
}

}  // namespace
}  // namespace tc
