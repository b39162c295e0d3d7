// Overlays (core/overlay.h, io/frame_overlay.h): the legend's ticks, labels and layout, label
// templates, the orientation triad, the overlay keys of the scene, and what drawOverlay puts into
// a frame: the bar's colours are the colormap's, its labels the range's numbers, the triad's axes
// point where the camera sees the world axes.
#include "core/overlay.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/color.h"
#include "core/colormap.h"
#include "core/error.h"
#include "core/generators.h"
#include "core/scene.h"
#include "core/styling.h"
#include "io/frame_overlay.h"

namespace tc {
namespace {

using nlohmann::json;

std::string sceneError(const std::string& overlay) {
    try {
        parseScene(json::parse(R"({"dataset": {"generate": "tornado"}, "overlay": )" + overlay + "}"), "scene.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

// ---- ticks and numbers -----------------------------------------------------------------------

TEST(Overlay, TickLabelsUseTheDecimalsTheStepNeeds) {
    EXPECT_EQ(formatLegendValue(0.25, 0.05), "0.25");
    EXPECT_EQ(formatLegendValue(0.2, 0.2), "0.2");
    EXPECT_EQ(formatLegendValue(1200, 200), "1200");
    EXPECT_EQ(formatLegendValue(-3, 1), "-3");
    EXPECT_EQ(formatLegendValue(-1e-17, 0.1), "0.0");  // a nice value computed with rounding error
    EXPECT_EQ(formatLegendValue(1.5e6, 5e5), "1.5e+06");
    EXPECT_EQ(formatLegendValue(2.5e-5, 5e-6), "2.5e-05");
    EXPECT_EQ(formatLegendValue(0.0123456, 0), "0.01235");  // no step: four significant digits
}

TEST(Overlay, TicksAreTheRangeEndsAndNiceValuesBetween) {
    const std::vector<LegendTick> ticks = legendTicks(0.0, 1.0, 6, 0.0f);
    std::vector<std::string> labels;
    for (const LegendTick& t : ticks) labels.push_back(t.label);
    EXPECT_EQ(labels, (std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"}));
    for (const LegendTick& t : ticks) EXPECT_NEAR(t.t, t.value, 1e-6);

    // An automatic range's ends are not on the step's grid: they read as the data's min and max.
    const std::vector<LegendTick> data = legendTicks(0.0123456, 0.987654, 5, 0.0f);
    EXPECT_EQ(data.front().label, "0.01235");
    EXPECT_EQ(data.back().label, "0.9877");
    EXPECT_FLOAT_EQ(data.front().t, 0.0f);
    EXPECT_FLOAT_EQ(data.back().t, 1.0f);
    for (std::size_t i = 1; i + 1 < data.size(); ++i) {
        EXPECT_NEAR(std::fmod(data[i].value + 1e-9, niceTickStep(0.0123456, 0.987654, 5)), 0.0, 1e-6) << data[i].label;
        EXPECT_NEAR(data[i].t, (data[i].value - 0.0123456) / (0.987654 - 0.0123456), 1e-6);
    }
}

TEST(Overlay, TicksCloseToAnEndAreLeftOut) {
    // 0.0 and 1.0 are nice values near the ends 0.01 and 0.99: they would overlap the end labels.
    for (const LegendTick& t : legendTicks(0.01, 0.99, 6, 0.08f)) {
        EXPECT_TRUE(t.t == 0.0f || t.t == 1.0f || (t.t >= 0.08f && t.t <= 0.92f)) << t.label;
    }
    EXPECT_EQ(legendTicks(2.0, 2.0, 5, 0.0f).size(), 1u);  // a constant attribute: one label
}

// ---- layout ----------------------------------------------------------------------------------

TEST(Overlay, LegendLayoutPlacesTheBarInFractionsFromTheBottomLeft) {
    LegendSpec spec;  // vertical, at [0.86, 0.15], 0.04 x 0.6
    const LegendLayout l = layoutLegend(spec, 200, 100, 0.0, 1.0);
    EXPECT_EQ(l.bar.x0, 172);
    EXPECT_EQ(l.bar.x1, 180);
    EXPECT_EQ(l.bar.y1, 85);
    EXPECT_EQ(l.bar.y0, 25);
    EXPECT_TRUE(l.labelsLeft);  // the bar is in the right half
    // The bar shows t from 0 at the bottom row to 1 at the top row, each pixel its centre's t.
    EXPECT_FLOAT_EQ(legendPixelT(l, 175, 84), 0.5f / 60.0f);
    EXPECT_FLOAT_EQ(legendPixelT(l, 175, 25), 59.5f / 60.0f);
    // Each tick's pixel shows a t within half a pixel of the tick's.
    for (std::size_t i = 0; i < l.ticks.size(); ++i)
        EXPECT_NEAR(legendPixelT(l, l.tickPixels[i].x, l.tickPixels[i].y), l.ticks[i].t, 0.5f / 60.0f + 1e-6f);

    spec.vertical = false;
    spec.position = {0.2f, 0.1f};
    spec.size = {0.6f, 0.04f};
    const LegendLayout h = layoutLegend(spec, 200, 100, 0.0, 1.0);
    EXPECT_FLOAT_EQ(legendPixelT(h, h.bar.x0, 0), 0.5f / 120.0f);
    for (std::size_t i = 0; i < h.ticks.size(); ++i) EXPECT_GT(h.labelAnchors[i].y, h.bar.y1);
}

// ---- label templates -------------------------------------------------------------------------

TEST(Overlay, LabelPlaceholdersAreReplaced) {
    const LabelValues v{7, 0.2333333, "speed", "rasterized"};
    EXPECT_EQ(expandLabel("frame {frame}", v), "frame 7");
    EXPECT_EQ(expandLabel("{frame:04}", v), "0007");
    EXPECT_EQ(expandLabel("t = {time} s", v), "t = 0.233333 s");
    EXPECT_EQ(expandLabel("t = {time:.2f}", v), "t = 0.23");
    EXPECT_EQ(expandLabel("{attribute} by {technique}", v), "speed by rasterized");
    EXPECT_EQ(expandLabel("{{literal}}", v), "{literal}");
    std::string error;
    EXPECT_EQ(expandLabel("{frames}", v, &error), "");
    EXPECT_NE(error.find("unknown placeholder {frames}"), std::string::npos) << error;
    EXPECT_EQ(expandLabel("frame {frame", v, &error), "");
    EXPECT_NE(error.find("unmatched '{'"), std::string::npos) << error;
}

// ---- triad -----------------------------------------------------------------------------------

TEST(Overlay, TriadAxesFollowTheCamera) {
    Camera front;  // eye on +z looking at the origin, y up
    auto a = triadAxes(front);
    EXPECT_NEAR(a[0].screen.x, 1.0f, 1e-6f);  // X to the right
    EXPECT_NEAR(a[1].screen.y, 1.0f, 1e-6f);  // Y up
    EXPECT_NEAR(a[2].towardViewer, 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(a[2].screen), 0.0f, 1e-6f);

    Camera side;  // eye on +x: Z points to the left, X toward the viewer
    side.eye = {3.0f, 0.0f, 0.0f};
    a = triadAxes(side);
    EXPECT_NEAR(a[2].screen.x, -1.0f, 1e-6f);
    EXPECT_NEAR(a[0].towardViewer, 1.0f, 1e-6f);
    EXPECT_NEAR(a[1].screen.y, 1.0f, 1e-6f);
}

// ---- scene keys ------------------------------------------------------------------------------

TEST(Overlay, SceneKeysAreReadWithTheirDefaults) {
    const Scene none = parseScene(json::parse(R"({"dataset": {"generate": "tornado"}})"), "scene.json");
    EXPECT_FALSE(none.overlay.any());
    const Scene s = parseScene(json::parse(R"json({"dataset": {"generate": "tornado"},
        "overlay": {"legend": {"orientation": "horizontal", "title": "speed (m/s)", "ticks": 4,
                               "text_color": [1, 0, 0]},
                    "text": [{"content": "frame {frame}", "position": [0.5, 0.9], "size": 0.05, "align": "center"}],
                    "axes": {"corner": "top_right", "size": 0.15}, "in_exr": true},
        "output": {"video": {"file": "movie.mp4", "fps": 24}}})json"),
                               "dir/scene.json");
    ASSERT_TRUE(s.overlay.legend);
    EXPECT_FALSE(s.overlay.legend->vertical);
    EXPECT_FLOAT_EQ(s.overlay.legend->size.x, 0.6f);  // the horizontal bar's default
    EXPECT_EQ(s.overlay.legend->title, "speed (m/s)");
    EXPECT_EQ(s.overlay.legend->ticks, 4);
    EXPECT_EQ(*s.overlay.legend->textColor, glm::vec3(1, 0, 0));
    ASSERT_EQ(s.overlay.text.size(), 1u);
    EXPECT_EQ(s.overlay.text[0].align, TextAlign::Center);
    EXPECT_FLOAT_EQ(s.overlay.text[0].position.y, 0.9f);
    ASSERT_TRUE(s.overlay.axes);
    EXPECT_EQ(s.overlay.axes->corner, Corner::TopRight);
    EXPECT_TRUE(s.overlay.inExr);
    EXPECT_EQ(s.overlay.font, kDefaultOverlayFont);
    EXPECT_FLOAT_EQ(s.overlay.fps, 24.0f);  // {time} = frame / output.video.fps
    ASSERT_TRUE(s.output.video);
    EXPECT_EQ(s.output.video->crf, 18);

    const Scene t = parseScene(json::parse(R"({"dataset": {"generate": "tornado"},
        "overlay": {"legend": true, "axes": false, "font": "fonts/a.ttf"}})"),
                               "dir/scene.json");
    EXPECT_TRUE(t.overlay.legend);
    EXPECT_FALSE(t.overlay.axes);
    EXPECT_EQ(t.overlay.font, "dir/fonts/a.ttf");  // relative to the scene file
}

TEST(Overlay, BadOverlayKeysNameTheKey) {
    EXPECT_EQ(sceneError(R"({"legend": {"orientation": "diagonal"}})"),
              "scene.json: overlay.legend.orientation: expected one of \"vertical\", \"horizontal\", got \"diagonal\"");
    EXPECT_EQ(sceneError(R"({"legend": {"position": [0.5, 1.5]}})"),
              "scene.json: overlay.legend.position: expected [x, y] fractions of the image in [0, 1], got [0.5,1.5]");
    EXPECT_EQ(sceneError(R"({"legend": 3})"),
              "scene.json: overlay.legend: expected true, false or an object of settings, got 3");
    EXPECT_EQ(sceneError(R"({"text": [{"content": "{frame} of {total}"}]})"),
              "scene.json: overlay.text[0].content: unknown placeholder {total} (known: {frame}, {frame:04}, {time}, "
              "{time:.2f}, {attribute}, {technique})");
    EXPECT_EQ(sceneError(R"({"text": [{"position": [0, 0]}]})"),
              "scene.json: overlay.text[0].content: missing: the label's text, e.g. \"frame {frame}\"");
    EXPECT_EQ(sceneError(R"({"text": [{"content": "a", "colour": [1, 1, 1]}]})")
                  .rfind("scene.json: overlay.text[0].colour: unknown key (did you mean \"color\"?)", 0),
              0u);
    EXPECT_EQ(sceneError(R"({"axes": {"corner": "middle"}})"),
              "scene.json: overlay.axes.corner: expected one of \"bottom_left\", \"bottom_right\", \"top_left\", "
              "\"top_right\", got \"middle\"");
    EXPECT_EQ(sceneError(R"({"in_exr": "yes"})"), "scene.json: overlay.in_exr: expected true or false, got \"yes\"");
    EXPECT_EQ(sceneError(R"({"legends": true})").rfind("scene.json: overlay.legends: unknown key", 0), 0u);
}

TEST(Overlay, BadVideoKeysNameTheKey) {
    auto error = [](const std::string& output) {
        try {
            parseScene(json::parse(R"({"dataset": {"generate": "tornado"}, "output": )" + output + "}"), "scene.json");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("<no error>");
    };
    EXPECT_EQ(error(R"({"video": {"file": "movie.avi"}})"),
              "scene.json: output.video.file: expected a file name ending in .mp4 (H.264 in MP4), got \"movie.avi\"");
    EXPECT_EQ(error(R"({"video": {"file": "m.mp4", "crf": 60}})"),
              "scene.json: output.video.crf: expected integer 0..51, got 60");
    EXPECT_EQ(error(R"({"formats": ["exr"], "video": {"file": "m.mp4"}})"),
              "scene.json: output.video: the movie is encoded from the PNG frames: add \"png\" to output.formats");
}

// ---- drawing ---------------------------------------------------------------------------------

FrameImages blackFrame(int w, int h) {
    FrameImages f;
    f.width = w;
    f.height = h;
    f.rgba.assign(4 * std::size_t(w) * std::size_t(h), 0.0f);
    for (std::size_t i = 3; i < f.rgba.size(); i += 4) f.rgba[i] = 1.0f;
    return f;
}

glm::vec3 srgbAt(const FrameImages& f, int x, int y) {
    const float* p = &f.rgba[4 * (std::size_t(y) * std::size_t(f.width) + std::size_t(x))];
    return linearToSrgb(glm::vec3(p[0], p[1], p[2]));
}

TEST(Overlay, LegendBarShowsTheColormapAtEveryTick) {
    OverlaySpec spec;
    spec.legend.emplace();
    OverlayContent content;
    content.spec = &spec;
    content.colormap = &builtinColormap("viridis");
    content.range = {0.25f, 1.75f};
    content.title = "speed";
    FrameImages frame = blackFrame(320, 240);
    drawOverlay(frame, content);
    const LegendLayout l = layoutLegend(*spec.legend, 320, 240, 0.25, 1.75);
    ASSERT_GE(l.ticks.size(), 3u);
    for (std::size_t i = 0; i < l.ticks.size(); ++i) {
        const glm::vec3 expected = content.colormap->sampleSrgb(l.ticks[i].t);
        const glm::vec3 got = srgbAt(frame, l.tickPixels[i].x, l.tickPixels[i].y);
        // Half a pixel of t along a 144-pixel bar.
        EXPECT_NEAR(got.x, expected.x, 0.01f) << l.ticks[i].label;
        EXPECT_NEAR(got.y, expected.y, 0.01f) << l.ticks[i].label;
        EXPECT_NEAR(got.z, expected.z, 0.01f) << l.ticks[i].label;
    }
}

// The pixels of `text` as render_text draws it alone onto black at the same anchor.
FrameImages textAlone(int w, int h, glm::ivec2 at, const std::string& text, int px) {
    FrameImages f = blackFrame(w, h);
    OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, 4, OIIO::TypeDesc::FLOAT), f.rgba.data());
    const float white[4] = {1, 1, 1, 1};
    EXPECT_TRUE(OIIO::ImageBufAlgo::render_text(buf, at.x, at.y, text, px, kDefaultOverlayFont, white,
                                                OIIO::ImageBufAlgo::TextAlignX::Right,
                                                OIIO::ImageBufAlgo::TextAlignY::Center));
    return f;
}

// Largest difference of the red channel in the band of rows [y - px, y + px) left of x.
float bandDifference(const FrameImages& a, const FrameImages& b, glm::ivec2 at, int px) {
    float worst = 0;
    for (int y = std::max(0, at.y - px); y < std::min(a.height, at.y + px); ++y)
        for (int x = 0; x <= at.x; ++x) {
            const std::size_t i = 4 * (std::size_t(y) * std::size_t(a.width) + std::size_t(x));
            worst = std::max(worst, std::abs(a.rgba[i] - b.rgba[i]));
        }
    return worst;
}

TEST(Overlay, LegendLabelsReadAsTheRange) {
    if (!std::filesystem::exists(kDefaultOverlayFont))
        GTEST_SKIP() << kDefaultOverlayFont << " missing (fonts-dejavu-core)";
    OverlaySpec spec;
    spec.legend.emplace();  // untitled: content.title is empty
    OverlayContent content;
    content.spec = &spec;
    content.colormap = &builtinColormap("viridis");
    content.range = {0.25f, 1.75f};
    FrameImages frame = blackFrame(320, 240);
    drawOverlay(frame, content);
    const LegendLayout l = layoutLegend(*spec.legend, 320, 240, 0.25, 1.75);
    EXPECT_EQ(l.ticks.front().label, "0.25");
    EXPECT_EQ(l.ticks.back().label, "1.75");
    for (std::size_t i = 0; i < l.ticks.size(); ++i) {
        const glm::ivec2 at = l.labelAnchors[i];
        // The label's rows left of the tick mark hold exactly the label (white on black) ...
        EXPECT_LT(bandDifference(frame, textAlone(320, 240, at, l.ticks[i].label, l.fontPx), at, l.fontPx / 2), 1e-6f)
            << l.ticks[i].label;
        // ... and not another number.
        EXPECT_GT(bandDifference(frame, textAlone(320, 240, at, "9.99", l.fontPx), at, l.fontPx / 2), 0.5f);
    }
}

// Centroid of the pixels whose sRGB colour is near `c`, relative to `origin` (x right, y up).
glm::vec2 centroidOf(const FrameImages& f, const glm::vec3& c, glm::vec2 origin, int* count) {
    glm::vec2 sum(0.0f);
    *count = 0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x)
            if (glm::length(srgbAt(f, x, y) - c) < 0.05f) {
                sum += glm::vec2(float(x) + 0.5f - origin.x, origin.y - (float(y) + 0.5f));
                ++*count;
            }
    return *count ? sum / float(*count) : sum;
}

TEST(Overlay, TriadPointsWhereTheCameraSeesTheAxes) {
    OverlaySpec spec;
    spec.axes.emplace();
    spec.axes->labels = false;
    spec.axes->size = 0.2f;
    const TriadLayout t = layoutTriad(*spec.axes, 200, 200);
    const glm::vec3 red{0.95f, 0.2f, 0.2f}, green{0.2f, 0.85f, 0.2f}, blue{0.3f, 0.45f, 1.0f};

    OverlayContent content;
    content.spec = &spec;
    FrameImages front = blackFrame(200, 200);  // the default camera: eye on +z, y up
    drawOverlay(front, content);
    int n = 0;
    const glm::vec2 x = centroidOf(front, red, t.origin, &n);
    ASSERT_GT(n, 10);
    EXPECT_GT(x.x, 0.3f * t.length);  // X to the right
    EXPECT_LT(std::abs(x.y), 2.0f);
    const glm::vec2 y = centroidOf(front, green, t.origin, &n);
    ASSERT_GT(n, 10);
    EXPECT_GT(y.y, 0.3f * t.length);  // Y up
    EXPECT_LT(std::abs(y.x), 2.0f);

    content.camera.eye = {3.0f, 0.0f, 0.0f};  // looking down -x: Z to the left
    FrameImages side = blackFrame(200, 200);
    drawOverlay(side, content);
    const glm::vec2 z = centroidOf(side, blue, t.origin, &n);
    ASSERT_GT(n, 10);
    EXPECT_LT(z.x, -0.3f * t.length);
    EXPECT_LT(std::abs(z.y), 2.0f);
    const glm::vec2 ySide = centroidOf(side, green, t.origin, &n);
    EXPECT_GT(ySide.y, 0.3f * t.length);
}

TEST(Overlay, AutomaticTextColourContrastsWithTheBackground) {
    EXPECT_EQ(automaticTextColor({0, 0, 0, 1}), glm::vec3(1.0f));
    EXPECT_EQ(automaticTextColor({1, 1, 1, 1}), glm::vec3(0.0f));
    EXPECT_EQ(automaticTextColor({1, 1, 1, 0}), glm::vec3(1.0f));  // transparent: as over black
}

TEST(Overlay, ColorMappingRangeIsTheStylingRange) {
    const LineSet lines = generateTornado(10, 20, 1);
    StyleSpec style;
    EXPECT_FALSE(colorMappingRange(lines, style, "scene.json"));  // constant colour
    style.color.attribute = "speed";
    const std::optional<ValueRange> automatic = colorMappingRange(lines, style, "scene.json");
    ASSERT_TRUE(automatic);
    EXPECT_EQ(automatic->lo, lines.attributes[0].min);
    EXPECT_EQ(automatic->hi, lines.attributes[0].max);
    style.color.range.automatic = false;
    style.color.range.lo = -1;
    style.color.range.hi = 2;
    EXPECT_EQ(colorMappingRange(lines, style, "scene.json")->hi, 2.0f);
}

}  // namespace
}  // namespace tc
