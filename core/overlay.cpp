#include "core/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>

namespace tc {

namespace {

// Heckbert's nicenum: a number of the form {1, 2, 5} x 10^k close to x (rounded), or not below
// it (ceiling).
double niceNumber(double x, bool round) {
    const double exponent = std::floor(std::log10(x));
    const double fraction = x / std::pow(10.0, exponent);
    double nice;
    if (round)
        nice = fraction < 1.5 ? 1 : fraction < 3 ? 2 : fraction < 7 ? 5 : 10;
    else
        nice = fraction <= 1 ? 1 : fraction <= 2 ? 2 : fraction <= 5 ? 5 : 10;
    return nice * std::pow(10.0, exponent);
}

std::string printfDouble(const char* format, int precision, double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, precision, value);
    return buffer;
}

// "-0", "-0.00", "-0e+00": the sign of a value that rounds to zero says nothing.
std::string dropNegativeZero(std::string s) {
    if (!s.empty() && s[0] == '-' && s.find_first_of("123456789") == std::string::npos) s.erase(0, 1);
    return s;
}

// Whether `value` is (to rounding) an integer multiple of `step`.
bool onStep(double value, double step) {
    const double k = value / step;
    return std::abs(k - std::round(k)) < 1e-6;
}

}  // namespace

double niceTickStep(double lo, double hi, int count) {
    if (!(hi > lo)) return 0.0;
    const double span = niceNumber(hi - lo, false);
    return niceNumber(span / std::max(count - 1, 1), true);
}

std::string formatLegendValue(double value, double step) {
    if (!std::isfinite(value)) return value != value ? "nan" : value > 0 ? "inf" : "-inf";
    if (!(step > 0)) return dropNegativeZero(printfDouble("%.*g", 4, value));
    if (std::abs(value) < 0.5 * step) value = 0;  // a nice value computed as 1e-17
    if (std::abs(value) >= 1e5 || step < 1e-3) {
        if (value == 0) return "0";
        // As many mantissa digits as resolve the step at the value's magnitude.
        const int digits =
            std::max(0, int(std::floor(std::log10(std::abs(value)))) - int(std::floor(std::log10(step) + 1e-9)));
        return dropNegativeZero(printfDouble("%.*e", std::min(digits, 15), value));
    }
    const int decimals = std::max(0, -int(std::floor(std::log10(step) + 1e-9)));
    return dropNegativeZero(printfDouble("%.*f", decimals, value));
}

std::vector<LegendTick> legendTicks(double lo, double hi, int count, float minGap) {
    if (!(hi > lo)) return {{lo, 0.0f, formatLegendValue(lo, 0.0)}};
    const double step = niceTickStep(lo, hi, count);
    const double span = hi - lo;
    // Ends on the step's grid print like the values between ("0.0" ... "1.0"); others with four
    // significant digits, so an automatic range's ends read as the data's minimum and maximum.
    auto endLabel = [&](double v) { return formatLegendValue(v, onStep(v, step) ? step : 0.0); };
    std::vector<LegendTick> ticks{{lo, 0.0f, endLabel(lo)}};
    for (double k = std::ceil(lo / step); k * step <= hi; k += 1) {
        const double v = k * step;
        const float t = float((v - lo) / span);
        if (t < minGap || t > 1.0f - minGap || v <= lo || v >= hi) continue;
        ticks.push_back({v, t, formatLegendValue(v, step)});
    }
    ticks.push_back({hi, 1.0f, endLabel(hi)});
    return ticks;
}

LegendLayout layoutLegend(const LegendSpec& spec, int width, int height, double lo, double hi) {
    LegendLayout l;
    l.vertical = spec.vertical;
    l.fontPx = std::max(6, int(std::lround(spec.fontSize * float(height))));
    l.tickLength = std::max(2, l.fontPx / 3);
    const int gap = std::max(2, l.fontPx / 4);
    PixelRect& bar = l.bar;
    bar.x0 = int(std::lround(spec.position.x * float(width)));
    bar.x1 = bar.x0 + std::max(1, int(std::lround(spec.size.x * float(width))));
    bar.y1 = height - int(std::lround(spec.position.y * float(height)));
    bar.y0 = bar.y1 - std::max(1, int(std::lround(spec.size.y * float(height))));

    const int along = l.vertical ? bar.height() : bar.width();
    float minGap;
    if (l.vertical) {
        minGap = 1.2f * float(l.fontPx) / float(along);
    } else {
        // Without the font's metrics here: DejaVu Sans digits are 0.64 em wide.
        const std::size_t chars = std::max(formatLegendValue(lo, 0).size(), formatLegendValue(hi, 0).size());
        minGap = (0.64f * float(l.fontPx) * float(chars) + float(l.fontPx)) / float(along);
    }
    l.ticks = legendTicks(lo, hi, spec.ticks, minGap);
    l.labelsLeft = l.vertical && 2 * (bar.x0 + bar.x1) > 2 * width;
    for (const LegendTick& tick : l.ticks) {
        const int k = std::clamp(int(std::floor(tick.t * float(along))), 0, along - 1);
        if (l.vertical) {
            const glm::ivec2 p{(bar.x0 + bar.x1) / 2, bar.y1 - 1 - k};
            l.tickPixels.push_back(p);
            l.labelAnchors.push_back(
                {l.labelsLeft ? bar.x0 - l.tickLength - gap : bar.x1 - 1 + l.tickLength + gap, p.y});
        } else {
            const glm::ivec2 p{bar.x0 + k, (bar.y0 + bar.y1) / 2};
            l.tickPixels.push_back(p);
            l.labelAnchors.push_back({p.x, bar.y1 - 1 + l.tickLength + gap});
        }
    }
    // Above the bar, clear of the top label of a vertical bar (centred on the bar's top row).
    l.titleAnchor = {(bar.x0 + bar.x1) / 2, bar.y0 - gap - (l.vertical ? l.fontPx / 2 : 0)};
    return l;
}

float legendPixelT(const LegendLayout& layout, int x, int y) {
    const PixelRect& b = layout.bar;
    return layout.vertical ? (float(b.y1 - y) - 0.5f) / float(b.height()) : (float(x - b.x0) + 0.5f) / float(b.width());
}

std::string expandLabel(const std::string& content, const LabelValues& values, std::string* error) {
    auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return std::string();
    };
    static const std::regex frameFormat(R"(0?(\d{1,2}))"), timeFormat(R"(\.(\d{1,2})f)");
    std::string out;
    for (std::size_t i = 0; i < content.size(); ++i) {
        const char c = content[i];
        if (c == '}') {
            if (i + 1 < content.size() && content[i + 1] == '}') {
                out += '}';
                ++i;
                continue;
            }
            return fail("unmatched '}' at character " + std::to_string(i + 1) + " (write \"}}\" for a brace)");
        }
        if (c != '{') {
            out += c;
            continue;
        }
        if (i + 1 < content.size() && content[i + 1] == '{') {
            out += '{';
            ++i;
            continue;
        }
        const std::size_t close = content.find('}', i);
        if (close == std::string::npos)
            return fail("unmatched '{' at character " + std::to_string(i + 1) + " (write \"{{\" for a brace)");
        const std::string inner = content.substr(i + 1, close - i - 1);
        const std::size_t colon = inner.find(':');
        const std::string name = inner.substr(0, colon);
        const std::string format = colon == std::string::npos ? "" : inner.substr(colon + 1);
        const bool formatted = colon != std::string::npos;
        std::smatch m;
        if (name == "frame") {
            if (formatted && !std::regex_match(format, m, frameFormat))
                return fail("{frame:" + format + "}: expected a width such as {frame:04}");
            std::string number = std::to_string(values.frame);
            const std::size_t width = formatted ? std::size_t(std::stoi(m[1].str())) : 0;
            if (number.size() < width) number.insert(0, width - number.size(), '0');
            out += number;
        } else if (name == "time") {
            if (formatted && !std::regex_match(format, m, timeFormat))
                return fail("{time:" + format + "}: expected decimals such as {time:.2f}");
            out += formatted ? printfDouble("%.*f", std::stoi(m[1].str()), values.time)
                             : printfDouble("%.*g", 6, values.time);
        } else if ((name == "attribute" || name == "technique") && !formatted) {
            out += name == "attribute" ? values.attribute : values.technique;
        } else {
            return fail("unknown placeholder {" + inner + "} (known: {frame}, {frame:04}, {time}, {time:.2f}, " +
                        "{attribute}, {technique})");
        }
        i = close;
    }
    return out;
}

std::array<TriadAxis, 3> triadAxes(const Camera& camera) {
    // The view rotation: camera space has x to the right, y up and the viewer on +z.
    const glm::mat3 view(camera.worldToCamera());
    std::array<TriadAxis, 3> axes;
    for (int i = 0; i < 3; ++i) {
        glm::vec3 e(0.0f);
        e[i] = 1.0f;
        const glm::vec3 d = view * e;
        axes[std::size_t(i)] = {{d.x, d.y}, d.z};
    }
    return axes;
}

TriadLayout layoutTriad(const AxesSpec& spec, int width, int height) {
    TriadLayout t;
    t.length = std::max(4.0f, spec.size * float(height));
    // Room for an axis in any direction plus its label beyond the tip.
    const float margin = 1.45f * t.length + 2.0f;
    const bool left = spec.corner == Corner::BottomLeft || spec.corner == Corner::TopLeft;
    const bool bottom = spec.corner == Corner::BottomLeft || spec.corner == Corner::BottomRight;
    t.origin = {left ? margin : float(width) - margin, bottom ? float(height) - margin : margin};
    return t;
}

}  // namespace tc
