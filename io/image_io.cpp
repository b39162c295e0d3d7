#include "io/image_io.h"

#include <OpenImageIO/half.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>

#include "core/error.h"
#include "core/srgb8.h"
#include "io/atomic_file.h"

namespace tc {

namespace {

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// OIIO reports some errors on the object and some (failed create/open) globally.
std::string oiioError(const std::string& objectError) {
    std::string message = objectError.empty() ? OIIO::geterror() : objectError;
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
    return message.empty() ? "unknown OpenImageIO error" : message;
}

// Rows converted per write_scanlines call: the conversion buffer holds this many rows, not the
// image, so a 16384^2 frame (rendered in tiles) needs no second full-size copy of its pixels.
constexpr int kRowsPerStrip = 64;

// Writes the image to a temp file next to `path` and renames it into place. `fillRows(y0, y1,
// dst)` writes rows [y0, y1) in `format` (native per-channel layout when spec.channelformats is
// set; TypeDesc::UNKNOWN) to dst, `rowBytes` per row; rows go out top to bottom in strips.
void writeImage(const std::string& path, const ImageSpec& spec, TypeDesc format, std::size_t rowBytes,
                const std::function<void(int, int, unsigned char*)>& fillRows, const char* what) {
    AtomicFile file(path);
    const std::string prefix = path + ": cannot write " + what + ": ";
    auto out = ImageOutput::create(file.tempPath());
    if (!out) throw OutputError(prefix + oiioError(""));
    if (!out->open(file.tempPath(), spec)) throw OutputError(prefix + oiioError(out->geterror()));
    std::vector<unsigned char> strip(rowBytes * std::size_t(std::min(spec.height, kRowsPerStrip)));
    for (int y0 = 0; y0 < spec.height; y0 += kRowsPerStrip) {
        const int y1 = std::min(spec.height, y0 + kRowsPerStrip);
        fillRows(y0, y1, strip.data());
        if (!out->write_scanlines(y0, y1, 0, format, strip.data())) {
            std::string message = oiioError(out->geterror());
            out->close();
            throw OutputError(prefix + message);
        }
    }
    if (!out->close()) throw OutputError(prefix + oiioError(out->geterror()));
    file.commit();
}

std::unique_ptr<ImageInput> openInput(const std::string& path, const ImageSpec* config = nullptr) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    auto in = ImageInput::open(path, config);
    if (!in) throw InputError(path + ": cannot read image: " + oiioError(""));
    return in;
}

int channelIndex(const ImageSpec& spec, const char* name) {
    for (int c = 0; c < spec.nchannels; ++c)
        if (spec.channelnames[std::size_t(c)] == name) return c;
    return -1;
}

float clamp01(float v) {
    return std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
}

std::uint8_t quantise(float v) {
    return std::uint8_t(std::lround(clamp01(v) * 255.0f));
}

// quantise(v) == 255 without the rounding call: lround rounds halves away from zero, so the code is
// 255 exactly when clamp01(v) * 255 >= 254.5 (NaN: clamp01 gives 0); the two agree on every float.
bool quantisesTo255(float v) {
    return clamp01(v) * 255.0f >= 254.5f;
}

bool everyAlphaQuantisesTo255(const FrameImages& frame) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, frame.pixelCount(), 1 << 16), true,
        [&](const tbb::blocked_range<std::size_t>& range, bool all) {
            for (std::size_t i = range.begin(); all && i != range.end(); ++i)
                all = quantisesTo255(frame.rgba[4 * i + 3]);
            return all;
        },
        [](bool a, bool b) { return a && b; });
}

// `count` premultiplied linear RGBA float pixels as straight sRGB 8-bit, Channels 3 (RGB: every
// alpha rounds to 255) or 4. A pixel with the bits of the one before it encodes to its bytes:
// rendered frames are mostly runs of background, so most pixels cost a 16-byte compare and a
// copy instead of three table lookups (writePng of a 1080p frame of configs/bench/spiral_1m.json,
// 75 % background: docs/performance.md, "Design notes"). The channel count is a template
// argument so that copy is inline, not a call per pixel.
template <int Channels>
void encodePixels(const float* rgba, std::size_t count, std::uint8_t* out, const Srgb8Encoder& srgb8) {
    const std::uint8_t* previous = nullptr;
    for (std::size_t i = 0; i != count; ++i, rgba += 4, out += Channels) {
        if (previous && std::memcmp(rgba, rgba - 4, 4 * sizeof(float)) == 0) {
            std::memcpy(out, previous, Channels);
            previous = out;
            continue;
        }
        previous = out;
        const float alpha = clamp01(rgba[3]);
        if (alpha <= 0.0f) {
            std::memset(out, 0, Channels);
            continue;
        }
        // Straight colour; x / 1 is x, so opaque pixels skip the divisions.
        if (alpha == 1.0f)
            for (int c = 0; c < 3; ++c) out[c] = srgb8(rgba[c]);
        else
            for (int c = 0; c < 3; ++c) out[c] = srgb8(rgba[c] / alpha);
        if constexpr (Channels == 4) out[3] = quantise(alpha);
    }
}

}  // namespace

void writePng(const FrameImages& frame, const std::string& path, const std::map<std::string, std::string>& text,
              int zlibLevel, PngAlpha alphaHint) {
    TC_CHECK(frame.width > 0 && frame.height > 0);
    TC_CHECK_OP(frame.rgba.size(), ==, 4 * frame.pixelCount());
    TC_CHECK(zlibLevel >= 0 && zlibLevel <= 9);
    const std::size_t w = std::size_t(frame.width);
    // A frame composited over an opaque background has alpha 1 everywhere: then RGB, a quarter
    // less to deflate (the serial part of the write) and a smaller file with the same pixels.
    // Told so, no scan (a pass over the 33 MB of a 1080p frame, ~4 CPU ms).
    const bool opaque = alphaHint == PngAlpha::Opaque || everyAlphaQuantisesTo255(frame);
    const int channels = opaque ? 3 : 4;
    // Strips of rows (writeImage), each converted in parallel and sRGB by table (core/srgb8.h):
    // with the formula, three powf per pixel cost more than the compression (docs/performance.md,
    // "Design notes").
    const Srgb8Encoder& srgb8 = srgb8Encoder();
    auto fillRows = [&](int y0, int y1, unsigned char* pixels) {
        const std::size_t first = std::size_t(y0) * w;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(first, std::size_t(y1) * w, 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              std::uint8_t* out = pixels + std::size_t(channels) * (range.begin() - first);
                              if (opaque)
                                  encodePixels<3>(&frame.rgba[4 * range.begin()], range.size(), out, srgb8);
                              else
                                  encodePixels<4>(&frame.rgba[4 * range.begin()], range.size(), out, srgb8);
                          });
    };
    ImageSpec spec(frame.width, frame.height, channels, TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("png:compressionLevel", zlibLevel);
    // No row filter (PNG_FILTER_NONE): libpng's default tries all five per row, which cost more
    // than the deflate itself; on a rendered 1920x1080 frame (large flat background, shaded tubes)
    // unfiltered level 1 was 2.6x faster and 10 % smaller than filtered (docs/performance.md,
    // "Design notes").
    spec.attribute("png:filter", 8);
    // Without this, OIIO's PNG writer treats the data as premultiplied and divides by alpha
    // again (pngoutput: "oiio:UnassociatedAlpha" = 1 means the data is already straight).
    spec.attribute("oiio:UnassociatedAlpha", 1);
    for (const auto& [key, value] : text) spec.attribute(key, value);  // string -> tEXt chunk
    writeImage(path, spec, TypeDesc::UINT8, std::size_t(channels) * w, fillRows, "PNG");
}

void writeExr(const FrameImages& frame, const std::string& path, const ExrOptions& options) {
    TC_CHECK(frame.width > 0 && frame.height > 0);
    const std::size_t n = frame.pixelCount();
    TC_CHECK_OP(frame.rgba.size(), ==, 4 * n);

    struct Channel {
        const char* name;
        TypeDesc type;
        const void* source;  // float or uint32 per pixel, at `stride` elements
        int stride;
    };
    std::vector<Channel> channels;
    channels.push_back({"R", TypeDesc::HALF, frame.rgba.data() + 0, 4});
    channels.push_back({"G", TypeDesc::HALF, frame.rgba.data() + 1, 4});
    channels.push_back({"B", TypeDesc::HALF, frame.rgba.data() + 2, 4});
    channels.push_back({"A", TypeDesc::HALF, frame.rgba.data() + 3, 4});
    if (options.depth) {
        TC_CHECK_OP(frame.depth.size(), ==, n);
        channels.push_back({"Z", TypeDesc::FLOAT, frame.depth.data(), 1});
    }
    if (options.normal) {
        TC_CHECK_OP(frame.normal.size(), ==, 3 * n);
        channels.push_back({"N.X", TypeDesc::FLOAT, frame.normal.data() + 0, 3});
        channels.push_back({"N.Y", TypeDesc::FLOAT, frame.normal.data() + 1, 3});
        channels.push_back({"N.Z", TypeDesc::FLOAT, frame.normal.data() + 2, 3});
    }
    if (options.id) {
        TC_CHECK_OP(frame.id.size(), ==, n);
        channels.push_back({"id", TypeDesc::UINT32, frame.id.data(), 1});
    }
    if (options.ao && !frame.ao.empty()) {
        TC_CHECK_OP(frame.ao.size(), ==, n);
        channels.push_back({"AO", TypeDesc::HALF, frame.ao.data(), 1});
    }

    ImageSpec spec(frame.width, frame.height, int(channels.size()), TypeDesc::HALF);
    spec.channelnames.clear();
    spec.channelformats.clear();
    std::size_t pixelBytes = 0;
    for (const Channel& ch : channels) {
        spec.channelnames.emplace_back(ch.name);
        spec.channelformats.push_back(ch.type);
        pixelBytes += ch.type.size();
    }
    spec.alpha_channel = 3;
    spec.z_channel = options.depth ? 4 : -1;
    spec.attribute("compression", "zip");
    for (const auto& [key, value] : options.metadata) spec.attribute(key, value);
    for (const auto& [key, value] : options.floats) spec.attribute(key, value);
    for (const auto& [key, m] : options.matrices) spec.attribute(key, OIIO::TypeMatrix44, m.data());

    // Mixed channel formats: OIIO takes one interleaved buffer in the native per-channel types
    // (TypeUnknown below). The id channel must not pass through float: ids above 2^24 would
    // round, and 0xFFFFFFFF would not survive.
    const std::size_t w = std::size_t(frame.width);
    auto fillRows = [&](int y0, int y1, unsigned char* pixels) {
        for (std::size_t i = std::size_t(y0) * w; i < std::size_t(y1) * w; ++i) {
            unsigned char* dst = &pixels[(i - std::size_t(y0) * w) * pixelBytes];
            for (const Channel& ch : channels) {
                if (ch.type == TypeDesc::HALF) {
                    Imath::half h(static_cast<const float*>(ch.source)[i * std::size_t(ch.stride)]);
                    std::memcpy(dst, &h, sizeof h);
                } else if (ch.type == TypeDesc::FLOAT) {
                    std::memcpy(dst, static_cast<const float*>(ch.source) + i * std::size_t(ch.stride), 4);
                } else {
                    std::memcpy(dst, static_cast<const std::uint32_t*>(ch.source) + i * std::size_t(ch.stride), 4);
                }
                dst += ch.type.size();
            }
        }
    };
    writeImage(path, spec, TypeDesc::UNKNOWN, pixelBytes * w, fillRows, "EXR");
}

FrameImages readExr(const std::string& path, std::map<std::string, std::string>* metadata) {
    auto in = openInput(path);
    const ImageSpec spec = in->spec();
    const std::string prefix = path + ": cannot read EXR: ";
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
        throw InputError(path + ": unsupported image dimensions");
    const int nch = spec.nchannels;
    FrameImages frame;
    frame.width = spec.width;
    frame.height = spec.height;
    const std::size_t n = frame.pixelCount();

    std::vector<float> all(n * std::size_t(nch));
    if (!in->read_image(0, 0, 0, nch, TypeDesc::FLOAT, all.data()))
        throw InputError(prefix + oiioError(in->geterror()));
    auto gather = [&](std::vector<float>& dst, std::initializer_list<const char*> names, bool required) {
        std::vector<int> idx;
        for (const char* name : names) idx.push_back(channelIndex(spec, name));
        bool present = std::all_of(idx.begin(), idx.end(), [](int c) { return c >= 0; });
        if (!present) {
            if (required) throw InputError(path + ": missing channel " + names.begin()[0]);
            dst.clear();
            return;
        }
        dst.resize(n * idx.size());
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < idx.size(); ++k)
                dst[i * idx.size() + k] = all[i * std::size_t(nch) + std::size_t(idx[k])];
    };
    gather(frame.rgba, {"R", "G", "B"}, true);
    {
        std::vector<float> rgb = std::move(frame.rgba);
        std::vector<float> alpha;
        gather(alpha, {"A"}, false);
        frame.rgba.resize(4 * n);
        for (std::size_t i = 0; i < n; ++i) {
            for (int c = 0; c < 3; ++c) frame.rgba[4 * i + std::size_t(c)] = rgb[3 * i + std::size_t(c)];
            frame.rgba[4 * i + 3] = alpha.empty() ? 1.0f : alpha[i];
        }
    }
    gather(frame.depth, {"Z"}, false);
    gather(frame.normal, {"N.X", "N.Y", "N.Z"}, false);
    gather(frame.ao, {"AO"}, false);
    if (int c = channelIndex(spec, "id"); c >= 0) {
        frame.id.resize(n);
        if (!in->read_image(0, 0, c, c + 1, TypeDesc::UINT32, frame.id.data()))
            throw InputError(prefix + oiioError(in->geterror()));
    }
    if (metadata) {
        metadata->clear();
        for (const OIIO::ParamValue& p : spec.extra_attribs)
            if (p.type() == OIIO::TypeString) (*metadata)[p.name().string()] = p.get_string();
    }
    return frame;
}

std::map<std::string, std::string> verifyImage(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": cannot read image: is a directory");
    auto in = openInput(path);
    const ImageSpec spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw InputError(path + ": unsupported image dimensions");
    // Every pixel of every channel, as float: OpenEXR and libpng report missing or corrupt
    // scanlines here, not when the header is opened.
    std::vector<float> all(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(std::max(spec.depth, 1)) *
                           std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, all.data()))
        throw InputError(path + ": cannot read image: " + oiioError(in->geterror()));
    std::map<std::string, std::string> metadata;
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        if (p.type() == OIIO::TypeString) metadata[p.name().string()] = p.get_string();
    return metadata;
}

RgbaImage readImageRgba(const std::string& path) {
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // PNG: straight alpha as stored
    auto in = openInput(path, &config);
    const ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels <= 0)
        throw InputError(path + ": unsupported image dimensions");
    const int nch = spec.nchannels;
    RgbaImage image;
    image.width = spec.width;
    image.height = spec.height;
    const std::size_t n = std::size_t(spec.width) * std::size_t(spec.height);
    std::vector<float> all(n * std::size_t(nch));
    if (!in->read_image(0, 0, 0, nch, TypeDesc::FLOAT, all.data()))
        throw InputError(path + ": cannot read image: " + oiioError(in->geterror()));

    int r = channelIndex(spec, "R"), g = channelIndex(spec, "G"), b = channelIndex(spec, "B");
    int a = spec.alpha_channel >= 0 ? spec.alpha_channel : channelIndex(spec, "A");
    if (r < 0 || g < 0 || b < 0) {
        // Unnamed channels: gray, gray+alpha, RGB, RGBA by position.
        bool gray = nch <= 2;
        r = 0;
        g = gray ? 0 : 1;
        b = gray ? 0 : 2;
        if (a < 0) a = (nch == 2 || nch >= 4) ? (gray ? 1 : 3) : -1;
    }
    image.rgba.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* px = &all[i * std::size_t(nch)];
        float* out = &image.rgba[4 * i];
        out[0] = px[r];
        out[1] = px[g];
        out[2] = px[b];
        out[3] = a >= 0 ? px[a] : 1.0f;
    }
    return image;
}

ImageDiff compareImages(const std::string& a, const std::string& b, float threshold) {
    RgbaImage ia = readImageRgba(a);
    RgbaImage ib = readImageRgba(b);
    if (ia.width != ib.width || ia.height != ib.height)
        throw InputError(a + ": image size " + std::to_string(ia.width) + "x" + std::to_string(ia.height) +
                         " differs from " + b + ": " + std::to_string(ib.width) + "x" + std::to_string(ib.height));
    ImageSpec spec(ia.width, ia.height, 4, TypeDesc::FLOAT);
    // ImageBuf wraps the buffers without copying; compare only reads them.
    OIIO::ImageBuf bufA(spec, ia.rgba.data());
    OIIO::ImageBuf bufB(spec, ib.rgba.data());
    OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(bufA, bufB, threshold, threshold);
    // r.error is not checked: OIIO sets it whenever some value exceeds failthresh (nfail > 0),
    // not only on real errors, and the buffers here are known to match in size and format.

    ImageDiff diff;
    diff.pixels = std::size_t(ia.width) * std::size_t(ia.height);
    diff.rmse = r.rms_error;
    diff.maxError = r.maxerror;
    // Our own PSNR rather than OIIO's so the formula is stated here: peak 1 over RGBA in 0..1.
    diff.psnr = diff.rmse > 0.0 ? 20.0 * std::log10(1.0 / diff.rmse) : std::numeric_limits<double>::infinity();
    diff.fractionOver = diff.pixels ? double(r.nfail) / double(diff.pixels) : 0.0;
    return diff;
}

}  // namespace tc
