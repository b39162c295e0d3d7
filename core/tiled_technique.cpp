#include "core/tiled_technique.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "core/error.h"

namespace tc {

TiledTechnique::TiledTechnique(std::unique_ptr<Technique> inner, TilePlan plan, int samples, KeptAovs keep)
    : m_inner(std::move(inner)),
      m_plan(std::move(plan)),
      m_offsets(sampleOffsets(samples)),
      m_nearest(nearestToCentre(m_offsets)),
      m_keep(keep) {
    TC_CHECK(!m_plan.tiles.empty());
}

void TiledTechnique::render(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    TC_CHECK(setup.window.isFull() && setup.window.fullWidth == 0);
    const int W = setup.width, H = setup.height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    out.width = W;
    out.height = H;
    out.rgba.assign(4 * n, 0.0f);
    // Unrequested AOVs stay empty; requested ones start as background.
    if (m_keep.depth)
        out.depth.assign(n, std::numeric_limits<float>::infinity());
    else
        out.depth.clear();
    if (m_keep.normal)
        out.normal.assign(3 * n, 0.0f);
    else
        out.normal.clear();
    if (m_keep.id)
        out.id.assign(n, kBackgroundId);
    else
        out.id.clear();
    out.ao.clear();

    const float invSamples = 1.0f / float(m_offsets.size());
    for (const TileRect& tile : m_plan.tiles) {
        TC_CHECK(tile.x + tile.width <= W && tile.y + tile.height <= H);
        for (std::size_t s = 0; s < m_offsets.size(); ++s) {
            FrameSetup ts = setup;
            ts.width = tile.width;
            ts.height = tile.height;
            ts.window = ImageWindow{W, H, tile.x, tile.y, m_offsets[s]};
            m_inner->render(ts, m_tile, timer);
            TC_CHECK(m_tile.width == tile.width && m_tile.height == tile.height);

            timer.begin("stitch");
            if (!m_tile.ao.empty() && out.ao.empty()) out.ao.assign(n, 0.0f);
            for (int row = 0; row < tile.height; ++row) {
                const std::size_t src = std::size_t(row) * std::size_t(tile.width);
                const std::size_t dst = std::size_t(tile.y + row) * std::size_t(W) + std::size_t(tile.x);
                const std::size_t w = std::size_t(tile.width);
                // Colour and AO: sums of the samples, divided once at the end.
                float* rgba = &out.rgba[4 * dst];
                const float* trgba = &m_tile.rgba[4 * src];
                for (std::size_t i = 0; i < 4 * w; ++i) rgba[i] += trgba[i];
                if (!m_tile.ao.empty())
                    for (std::size_t i = 0; i < w; ++i) out.ao[dst + i] += m_tile.ao[src + i];
                if (s != m_nearest) continue;  // first-surface AOVs: one sample's, never a blend
                if (m_keep.depth) std::memcpy(&out.depth[dst], &m_tile.depth[src], w * sizeof(float));
                if (m_keep.normal) std::memcpy(&out.normal[3 * dst], &m_tile.normal[3 * src], 3 * w * sizeof(float));
                if (m_keep.id) std::memcpy(&out.id[dst], &m_tile.id[src], w * sizeof(std::uint32_t));
            }
            timer.setItems(tile.pixelCount());
            timer.end();
        }
    }
    if (m_offsets.size() > 1) {
        for (float& v : out.rgba) v *= invSamples;
        for (float& v : out.ao) v *= invSamples;
    }
}

nlohmann::json TiledTechnique::describe() const {
    nlohmann::json j = m_inner->describe();
    j["tiles"] = {{"grid", {m_plan.nx, m_plan.ny}},
                  {"automatic", m_plan.automatic},
                  {"largest", {m_plan.largestTileWidth, m_plan.largestTileHeight}},
                  {"per_pixel_bytes", m_plan.bytesPerPixel},
                  {"largest_tile_mb", double(m_plan.largestTileBytes) / (1024.0 * 1024.0)}};
    j["samples"] = m_offsets.size();
    j["sample_pattern"] = "centred Hammersley set, box filter; depth/normal/id of the sample nearest the centre";
    return j;
}

std::unique_ptr<Technique> wrapInTiles(std::unique_ptr<Technique> inner, const TilePlan& plan, int samples,
                                       KeptAovs keep) {
    if (plan.tiles.size() <= 1 && samples <= 1) return inner;
    return std::make_unique<TiledTechnique>(std::move(inner), plan, samples, keep);
}

}  // namespace tc
