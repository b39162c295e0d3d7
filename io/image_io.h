#pragma once
// Frame images to and from files (OpenImageIO): PNG for viewing, multi-channel EXR for analysis,
// and a numeric image comparison for golden tests and `tubecast compare`.
#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/frame_images.h"

namespace tc {

// 8-bit PNG, sRGB, straight (unassociated) alpha; RGB without the alpha channel when every pixel
// rounds to alpha 255 (a frame over an opaque background). Each pixel's premultiplied linear colour
// is divided by its alpha (alpha 0 -> black), clamped to [0,1], encoded with linearToSrgb and
// rounded to the nearest 8-bit value. Written through an AtomicFile. `text` becomes PNG tEXt
// chunks (key -> value), e.g. the scene hash that --resume checks. `zlibLevel` 0..9 (zlib's
// scale; 6 is libpng's default), rows unfiltered: at 1920x1080 libpng's defaults cost more than a
// ray-traced frame, level 1 unfiltered a quarter of that (`scripts/bench/raytraced.sh 3 7 stages`).
// Throws OutputError "PATH: cannot write PNG: <reason>".
// `alpha` Opaque: the caller knows every alpha is 1 (a frame composited over an opaque
// background, core/compositing.h), so RGB is written without scanning the frame's alphas first.
constexpr int kPngFrameZlibLevel = 1;
enum class PngAlpha { Detect, Opaque };
void writePng(const FrameImages& frame, const std::string& path, const std::map<std::string, std::string>& text = {},
              int zlibLevel = kPngFrameZlibLevel, PngAlpha alpha = PngAlpha::Detect);

// Which optional EXR channels to write, and string metadata for the header (scene name,
// technique, tubecast version, ...). Keys are written as given.
struct ExrOptions {
    bool depth = true;
    bool normal = true;
    bool id = true;
    bool ao = false;  // written only when frame.ao is non-empty
    std::map<std::string, std::string> metadata;
    std::map<std::string, float> floats;                    // float attributes (render time)
    std::map<std::string, std::array<float, 16>> matrices;  // m44f attributes (worldToCamera):
    // the 16 values in glm's column-major order, which is Imath's row-major M44f of the same
    // transform for row vectors (p * M), the OpenEXR convention.
};

// OpenEXR, zip-compressed, one part. Channels:
//   R G B A      HALF   linear, premultiplied (the OpenEXR convention)
//   Z            FLOAT  view-space depth, +inf on background                (options.depth)
//   N.X N.Y N.Z  FLOAT  world-space normal, 0 on background                 (options.normal)
//   id           UINT   polyline index, 0xFFFFFFFF (kBackgroundId) on background (options.id)
//   AO           HALF   ambient occlusion                       (options.ao and frame.ao set)
// Written through an AtomicFile. Throws OutputError "PATH: cannot write EXR: <reason>".
void writeExr(const FrameImages& frame, const std::string& path, const ExrOptions& options);

// Reads an EXR written by writeExr (channels are looked up by name; missing optional ones
// leave the matching FrameImages vector empty, missing A reads as 1). `metadata`, if given,
// receives the header's string attributes. Throws InputError "PATH: ...".
FrameImages readExr(const std::string& path, std::map<std::string, std::string>* metadata = nullptr);

// Decodes every pixel of any image OpenImageIO reads (so a truncated or corrupt file fails) and
// returns its string metadata: EXR header attributes, PNG text chunks.
// Throws InputError "PATH: no such file" / "PATH: cannot read image: <reason>".
std::map<std::string, std::string> verifyImage(const std::string& path);

struct RgbaImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgba;  // 4 per pixel, row 0 = top
};

// Any image OpenImageIO reads, as float RGBA exactly as stored: PNG 8-bit values / 255 with
// straight alpha (OIIO would premultiply by default; we ask it not to), EXR linear
// premultiplied. Gray is replicated to RGB; a missing alpha reads as 1. Channels R, G, B, A
// are found by name when present, else the first channels are used.
// Throws InputError "PATH: no such file" / "PATH: cannot read image: <reason>".
RgbaImage readImageRgba(const std::string& path);

struct ImageDiff {
    double rmse = 0.0;          // over all RGBA values
    double psnr = 0.0;          // 20 log10(1 / rmse): peak 1 (values in 0..1); +inf when identical
    double maxError = 0.0;      // largest absolute difference of any channel
    double fractionOver = 0.0;  // fraction of pixels with any channel differing by > threshold
    std::size_t pixels = 0;
};

// Compares two images as read by readImageRgba (so a PNG and an EXR of the same frame compare
// their stored values, not colour-managed ones) with OIIO's ImageBufAlgo::compare.
// Throws InputError "A: image size WxH differs from B: WxH".
ImageDiff compareImages(const std::string& a, const std::string& b, float threshold);

}  // namespace tc
