#pragma once
// Overlays of the display outputs (docs/scene-spec.md "overlay"): a colour legend of the
// style.color mapping, text labels and an orientation triad, the way ParaView's scalar bar, text
// sources and orientation axes annotate a view. This file holds what is pure layout (positions in
// pixels, tick values and their labels, label templates, the triad's screen directions); drawing
// them with a font engine is io/frame_overlay.h's.
#include <array>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"

namespace tc {

// DejaVu Sans from the Debian package fonts-dejavu-core: overlay.font's default.
inline constexpr const char* kDefaultOverlayFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// overlay.legend: a colour bar of the style.color attribute mapping. Positions and sizes are
// fractions of the image, x from the left edge and y from the bottom edge (ParaView's normalised
// viewport coordinates).
struct LegendSpec {
    bool vertical = true;
    glm::vec2 position{0.86f, 0.15f};    // the bar's lower-left corner
    glm::vec2 size{0.04f, 0.6f};         // the bar's width (fraction of the image width), height (of the height)
    std::string title;                   // empty: the attribute's name
    int ticks = 5;                       // about this many labelled values, the range's ends included
    float fontSize = 0.035f;             // text height, fraction of the image height
    std::optional<glm::vec3> textColor;  // sRGB; unset: black or white against image.background
    bool directionKey = true;            // style.color "direction": a key of the three axes' colours
};

enum class TextAlign { Left, Center, Right };

// One entry of overlay.text.
struct TextLabelSpec {
    std::string content;               // with {frame}, {time}, {attribute}, {technique}
    glm::vec2 position{0.02f, 0.95f};  // of the text's baseline at `align`, fractions from the bottom-left
    float size = 0.04f;                // text height, fraction of the image height
    TextAlign align = TextAlign::Left;
    std::optional<glm::vec3> color;  // sRGB; unset as LegendSpec::textColor
};

enum class Corner { BottomLeft, BottomRight, TopLeft, TopRight };

// overlay.axes: an orientation triad of the world axes as the frame's camera sees them.
struct AxesSpec {
    Corner corner = Corner::BottomLeft;
    float size = 0.1f;   // an axis seen side-on, fraction of the image height
    bool labels = true;  // "X", "Y", "Z" at the tips
};

struct OverlaySpec {
    std::optional<LegendSpec> legend;
    std::vector<TextLabelSpec> text;
    std::optional<AxesSpec> axes;
    bool inExr = false;  // draw into the EXR's colour too (its AOVs are never touched)
    std::string font = kDefaultOverlayFont;
    // Seconds per animation frame for {time} where the data has no time: 1 / output.video.fps.
    float fps = 30.0f;

    bool any() const { return legend || !text.empty() || axes; }
};

// A pixel rectangle, row 0 at the top (the frame's layout): [x0, x1) x [y0, y1).
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

// A labelled value on the legend: its position t in [0,1] along the bar (0 at the range's low end)
// and its text.
struct LegendTick {
    double value = 0;
    float t = 0;
    std::string label;
};

// Values to label on a bar over [lo, hi]: both ends (as formatLegendValue gives them) and the "nice"
// numbers between (multiples of 1, 2 or 5 times a power of ten, Heckbert's "Nice numbers for graph
// labels", Graphics Gems 1990), about `count` in all; a nice value closer than `minGap` (in t) to
// an end is left out so labels do not overlap. lo == hi: one tick. Ascending in t.
std::vector<LegendTick> legendTicks(double lo, double hi, int count, float minGap);

// The step of the nice values legendTicks places over [lo, hi] for about `count` labels.
double niceTickStep(double lo, double hi, int count);

// A number as a legend shows it: fixed point with as many decimals as `step` (the tick spacing)
// needs and no more ("0.25", "1200", "-3"), scientific where fixed point would be long or lose
// the value (|v| >= 1e5 or a step below 1e-3: "1.5e+06", "2.5e-05"); -0 prints as 0. step <= 0:
// four significant digits.
std::string formatLegendValue(double value, double step);

// Where a legend goes in a width x height frame: the bar, the tick marks' and labels' anchors,
// the title's. Text anchors are pixel positions of a label's reference point: for a vertical bar
// the labels' vertical centre at the bar's side, for a horizontal bar the labels' top centre
// below it.
struct LegendLayout {
    PixelRect bar;
    bool vertical = true;
    bool labelsLeft = false;  // vertical: labels on the bar's left (the bar is in the image's right half)
    int fontPx = 12;
    int tickLength = 4;  // tick marks outside the bar, on the labels' side
    std::vector<LegendTick> ticks;
    std::vector<glm::ivec2> tickPixels;    // the bar pixel of each tick's value (centre line of the bar)
    std::vector<glm::ivec2> labelAnchors;  // per tick
    glm::ivec2 titleAnchor{0};             // bottom-centre of the title (above the bar)
};
LegendLayout layoutLegend(const LegendSpec& spec, int width, int height, double lo, double hi);

// The colormap coordinate t in [0,1] the bar shows at pixel (x, y) of the layout's bar: each
// pixel shows its centre's position along the bar (low end at the bottom or left).
float legendPixelT(const LegendLayout& layout, int x, int y);

// The values of a label template's placeholders for one frame.
struct LabelValues {
    int frame = 0;
    double time = 0;
    std::string attribute;  // the style.color attribute ("" when the colour is constant)
    std::string technique;
};

// Placeholders: {frame}, {frame:04} (zero-padded to the width), {time}, {time:.2f} (that many
// decimals; default: up to 6 significant digits), {attribute}, {technique}; "{{" and "}}" are
// literal braces. Returns "" and sets `error` for an unknown placeholder or an unmatched brace.
std::string expandLabel(const std::string& content, const LabelValues& values, std::string* error = nullptr);

// The world axes X, Y, Z as the camera sees them: each axis's direction in the image (x to the
// right, y up) and its component toward the viewer (positive: pointing out of the screen).
// An axis seen side-on has length 1; one along the view direction length 0.
struct TriadAxis {
    glm::vec2 screen{0.0f};
    float towardViewer = 0.0f;
};
std::array<TriadAxis, 3> triadAxes(const Camera& camera);

// The triad's origin in pixels (row 0 at the top) and its axis length in pixels.
struct TriadLayout {
    glm::vec2 origin{0.0f};
    float length = 0.0f;
};
TriadLayout layoutTriad(const AxesSpec& spec, int width, int height);

}  // namespace tc
