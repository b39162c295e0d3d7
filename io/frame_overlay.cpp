#include "io/frame_overlay.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/color.h"
#include "core/error.h"

namespace tc {

namespace {

using OIIO::ImageBuf;
namespace IBA = OIIO::ImageBufAlgo;

// The frame's colour as an ImageBuf over its own memory (no copy): render_text composites "over"
// into it, which on premultiplied values with an opaque text colour is the premultiplied over.
class Canvas {
public:
    explicit Canvas(FrameImages& frame)
        : m_frame(frame),
          m_buf(OIIO::ImageSpec(frame.width, frame.height, 4, OIIO::TypeDesc::FLOAT), frame.rgba.data()) {}

    int width() const { return m_frame.width; }
    int height() const { return m_frame.height; }

    // An opaque pixel of sRGB colour `srgb` (clipped to the image).
    void set(int x, int y, const glm::vec3& srgb) { blend(x, y, srgbToLinear(srgb), 1.0f); }

    // `srgb` over the pixel with coverage `a`.
    void blend(int x, int y, const glm::vec3& linear, float a) {
        if (x < 0 || y < 0 || x >= m_frame.width || y >= m_frame.height || a <= 0.0f) return;
        float* p = &m_frame.rgba[4 * (std::size_t(y) * std::size_t(m_frame.width) + std::size_t(x))];
        for (int c = 0; c < 3; ++c) p[c] = linear[c] * a + p[c] * (1.0f - a);
        p[3] = a + p[3] * (1.0f - a);
    }

    void fill(const PixelRect& r, const glm::vec3& srgb) {
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) set(x, y, srgb);
    }

    // Text of height `px` in sRGB colour `srgb` anchored at (x, y) as render_text aligns it.
    void text(int x, int y, const std::string& s, int px, const std::string& font, const glm::vec3& srgb,
              IBA::TextAlignX ax, IBA::TextAlignY ay) {
        if (s.empty()) return;
        const glm::vec3 linear = srgbToLinear(srgb);
        const float color[4] = {linear.x, linear.y, linear.z, 1.0f};
        if (!IBA::render_text(m_buf, x, y, s, px, font, color, ax, ay))
            throw InputError(font + ": cannot render text: " + m_buf.geterror());
    }

    // The text's extent as render_text would draw it left-aligned on the baseline at (0, 0).
    static OIIO::ROI measure(const std::string& s, int px, const std::string& font) {
        return IBA::text_size(s, px, font);
    }

    // A segment of width `w` pixels with antialiased edges, over the image. OIIO's render_line draws
    // one-pixel aliased lines only, too thin for a triad that should read at a glance.
    void segment(glm::vec2 a, glm::vec2 b, float w, const glm::vec3& srgb) {
        const glm::vec3 linear = srgbToLinear(srgb);
        const float r = 0.5f * w;
        const int x0 = int(std::floor(std::min(a.x, b.x) - r - 1)), x1 = int(std::ceil(std::max(a.x, b.x) + r + 1));
        const int y0 = int(std::floor(std::min(a.y, b.y) - r - 1)), y1 = int(std::ceil(std::max(a.y, b.y) + r + 1));
        const glm::vec2 d = b - a;
        const float len2 = std::max(glm::dot(d, d), 1e-12f);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const glm::vec2 p{float(x) + 0.5f, float(y) + 0.5f};
                const float s = std::clamp(glm::dot(p - a, d) / len2, 0.0f, 1.0f);
                const float dist = glm::length(p - (a + s * d));
                blend(x, y, linear, std::clamp(r + 0.5f - dist, 0.0f, 1.0f));
            }
    }

private:
    FrameImages& m_frame;
    ImageBuf m_buf;
};

glm::vec3 textColorOf(const std::optional<glm::vec3>& chosen, const glm::vec4& background) {
    return chosen ? *chosen : automaticTextColor(background);
}

// The title above the bar, moved sideways to stay inside the image.
// `anchor`: the title's bottom centre.
void drawTitle(Canvas& c, glm::ivec2 anchor, int px, const std::string& title, const std::string& font,
               const glm::vec3& color) {
    const OIIO::ROI size = Canvas::measure(title, px, font);
    int x = anchor.x;
    if (size.defined()) {
        const int half = size.width() / 2 + 1;
        x = std::clamp(x, half, std::max(half, c.width() - half));
    }
    c.text(x, anchor.y, title, px, font, color, IBA::TextAlignX::Center, IBA::TextAlignY::Bottom);
}

void drawColorBar(Canvas& c, const OverlayContent& o, const LegendSpec& spec) {
    const LegendLayout l = layoutLegend(spec, c.width(), c.height(), o.range.lo, o.range.hi);
    const glm::vec3 color = textColorOf(spec.textColor, o.background);
    const PixelRect& bar = l.bar;
    for (int y = bar.y0; y < bar.y1; ++y)
        for (int x = bar.x0; x < bar.x1; ++x) c.set(x, y, o.colormap->sampleSrgb(legendPixelT(l, x, y)));
    const int thickness = std::max(1, l.fontPx / 12);
    for (std::size_t i = 0; i < l.ticks.size(); ++i) {
        const glm::ivec2 p = l.tickPixels[i];
        // Tick marks outside the bar, so the bar's colour at a tick stays the colormap's.
        PixelRect mark;
        if (l.vertical) {
            mark = l.labelsLeft ? PixelRect{bar.x0 - l.tickLength, p.y, bar.x0, p.y + thickness}
                                : PixelRect{bar.x1, p.y, bar.x1 + l.tickLength, p.y + thickness};
        } else {
            mark = {p.x, bar.y1, p.x + thickness, bar.y1 + l.tickLength};
        }
        c.fill(mark, color);
        const glm::ivec2 a = l.labelAnchors[i];
        if (l.vertical)
            c.text(a.x, a.y, l.ticks[i].label, l.fontPx, o.spec->font, color,
                   l.labelsLeft ? IBA::TextAlignX::Right : IBA::TextAlignX::Left, IBA::TextAlignY::Center);
        else
            c.text(a.x, a.y, l.ticks[i].label, l.fontPx, o.spec->font, color, IBA::TextAlignX::Center,
                   IBA::TextAlignY::Top);
    }
    drawTitle(c, l.titleAnchor, l.fontPx, spec.title.empty() ? o.title : spec.title, o.spec->font, color);
}

// style.color "direction": three swatches of the colours a line along X, Y or Z gets (|t| as RGB).
void drawDirectionKey(Canvas& c, const OverlayContent& o, const LegendSpec& spec) {
    const glm::vec3 color = textColorOf(spec.textColor, o.background);
    const int px = std::max(6, int(std::lround(spec.fontSize * float(c.height()))));
    const int x0 = int(std::lround(spec.position.x * float(c.width())));
    const int bottom = c.height() - int(std::lround(spec.position.y * float(c.height())));
    const char* names[3] = {"X", "Y", "Z"};
    for (int i = 0; i < 3; ++i) {
        const int y1 = bottom - (2 - i) * (px + px / 3);
        glm::vec3 axis(0.0f);
        axis[i] = 1.0f;
        c.fill({x0, y1 - px, x0 + px, y1}, axis);
        c.text(x0 + px + px / 3, y1 - px / 2, names[i], px, o.spec->font, color, IBA::TextAlignX::Left,
               IBA::TextAlignY::Center);
    }
    const int top = bottom - 3 * px - 2 * (px / 3);
    drawTitle(c, {x0 + px, top - std::max(2, px / 4)}, px, spec.title.empty() ? "direction" : spec.title, o.spec->font,
              color);
}

void drawTriad(Canvas& c, const OverlayContent& o, const AxesSpec& spec) {
    const TriadLayout t = layoutTriad(spec, c.width(), c.height());
    const std::array<TriadAxis, 3> axes = triadAxes(o.camera);
    static const glm::vec3 kColors[3] = {{0.95f, 0.2f, 0.2f}, {0.2f, 0.85f, 0.2f}, {0.3f, 0.45f, 1.0f}};
    static const char* kNames[3] = {"X", "Y", "Z"};
    // Farthest first, so the axis toward the viewer is drawn on top.
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return axes[std::size_t(a)].towardViewer < axes[std::size_t(b)].towardViewer; });
    const float width = std::max(1.5f, t.length / 14.0f);
    const int fontPx = std::max(6, int(std::lround(0.32f * t.length)));
    for (int i : order) {
        const glm::vec2 dir{axes[std::size_t(i)].screen.x, -axes[std::size_t(i)].screen.y};  // image y is down
        const glm::vec2 tip = t.origin + t.length * dir;
        c.segment(t.origin, tip, width, kColors[i]);
        if (spec.labels) {
            const glm::vec2 at = t.origin + (t.length + 0.6f * float(fontPx)) * dir;
            c.text(int(std::lround(at.x)), int(std::lround(at.y)), kNames[i], fontPx, o.spec->font, kColors[i],
                   IBA::TextAlignX::Center, IBA::TextAlignY::Center);
        }
    }
}

// The label's baseline position from the bottom-left fractions.
void drawLabel(Canvas& c, const OverlayContent& o, const TextLabelSpec& label) {
    const std::string text = expandLabel(label.content, o.labels);
    const int px = std::max(6, int(std::lround(label.size * float(c.height()))));
    const int x = int(std::lround(label.position.x * float(c.width())));
    const int y = c.height() - int(std::lround(label.position.y * float(c.height())));
    const IBA::TextAlignX ax = label.align == TextAlign::Center  ? IBA::TextAlignX::Center
                               : label.align == TextAlign::Right ? IBA::TextAlignX::Right
                                                                 : IBA::TextAlignX::Left;
    c.text(x, y, text, px, o.spec->font, textColorOf(label.color, o.background), ax, IBA::TextAlignY::Baseline);
}

}  // namespace

glm::vec3 automaticTextColor(const glm::vec4& background) {
    // Relative luminance (Rec. 709) of the background as a viewer sees it over black; a light one
    // (above 18 % grey, about sRGB 0.46) gets black text.
    const glm::vec3 linear = srgbToLinear(glm::vec3(background));
    const float y = background.w * glm::dot(linear, glm::vec3(0.2126f, 0.7152f, 0.0722f));
    return y > 0.18f ? glm::vec3(0.0f) : glm::vec3(1.0f);
}

void drawOverlay(FrameImages& frame, const OverlayContent& content) {
    TC_CHECK(content.spec != nullptr);
    TC_CHECK_OP(frame.rgba.size(), ==, 4 * frame.pixelCount());
    const OverlaySpec& spec = *content.spec;
    Canvas canvas(frame);
    if (spec.legend) {
        if (content.colormap)
            drawColorBar(canvas, content, *spec.legend);
        else if (content.directionColors && spec.legend->directionKey)
            drawDirectionKey(canvas, content, *spec.legend);
    }
    if (spec.axes) drawTriad(canvas, content, *spec.axes);
    for (const TextLabelSpec& label : spec.text) drawLabel(canvas, content, label);
}

void requireOverlayFont(const std::string& font, const std::string& sceneFile) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(font, ec)) return;
    throw InputError((sceneFile.empty() ? std::string("scene") : sceneFile) + ": overlay.font: " + font +
                     ": no such file (the default is DejaVu Sans from the Debian package fonts-dejavu-core; "
                     "install it or set overlay.font to a TrueType font file)");
}

}  // namespace tc
