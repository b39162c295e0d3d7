#include "gl/radix_sort.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "gl/bindings.h"
#include "gl/gl_api.h"
#include "gl/shader_library.h"

namespace tc::gl {
namespace {

// Scan blocks: 64 lanes x 64 values. Only the top level of a 10^7-key sort is large
// (256 digits x 2442 tiles = 625k entries -> 153 blocks -> one block).
constexpr int kScanLanes = 64;
constexpr int kScanItemsPerLane = 64;
constexpr std::size_t kScanBlock = std::size_t(kScanLanes) * kScanItemsPerLane;

std::size_t divUp(std::size_t a, std::size_t b) {
    return (a + b - 1) / b;
}

GLint uniform(const Program& program, const char* name) {
    GLint location = glGetUniformLocation(program.id(), name);
    // Unused uniforms are optimised away (location -1); glProgramUniform ignores -1.
    return location;
}

void setUint(const Program& program, const char* name, std::size_t value) {
    glProgramUniform1ui(program.id(), uniform(program, name), static_cast<GLuint>(value));
}

std::size_t bufferSize(const Buffer& buffer) {
    GLint64 size = 0;
    glGetNamedBufferParameteri64v(buffer.id(), GL_BUFFER_SIZE, &size);
    return static_cast<std::size_t>(size);
}

void growBuffer(Buffer& buffer, std::size_t& capacity, std::size_t needed) {
    if (needed <= capacity && buffer) return;
    capacity = std::max(needed, capacity + capacity / 2);
    buffer = makeBuffer(capacity * sizeof(GLuint));
}

}  // namespace

RadixSort RadixSort::create(const Config& config) {
    TC_CHECK(config.digitBits == 4 || config.digitBits == 8);
    TC_CHECK(config.lanes >= 1 && config.itemsPerLane >= 1);
    GLint maxShared = 0;
    glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &maxShared);
    TC_CHECK_OP((std::size_t(1) << config.digitBits) * config.lanes * 4, <=, static_cast<std::size_t>(maxShared));

    RadixSort sort;
    sort.m_config = config;
    std::vector<std::string> defines = {
        "RADIX_BITS " + std::to_string(config.digitBits) + "u",
        "RADIX_LANES " + std::to_string(config.lanes) + "u",
        "RADIX_ITEMS_PER_LANE " + std::to_string(config.itemsPerLane) + "u",
    };
    sort.m_histogram = compileProgram({{GL_COMPUTE_SHADER, "radix_sort_histogram.comp"}}, defines);
    sort.m_scatter = compileProgram({{GL_COMPUTE_SHADER, "radix_sort_scatter.comp"}}, defines);
    std::vector<std::string> scanDefines = {
        "SCAN_LANES " + std::to_string(kScanLanes) + "u",
        "SCAN_ITEMS_PER_LANE " + std::to_string(kScanItemsPerLane) + "u",
    };
    sort.m_scan = compileProgram({{GL_COMPUTE_SHADER, "radix_sort_scan.comp"}}, scanDefines);
    scanDefines.push_back("RADIX_SCAN_REDUCE");
    sort.m_scanReduce = compileProgram({{GL_COMPUTE_SHADER, "radix_sort_scan.comp"}}, scanDefines);
    return sort;
}

void RadixSort::ensureScratch(std::size_t count) {
    std::size_t capacity = m_scratchCapacity;
    growBuffer(m_keysScratch, capacity, count);
    std::size_t valuesCapacity = m_scratchCapacity;
    growBuffer(m_valuesScratch, valuesCapacity, count);
    m_scratchCapacity = capacity;

    std::size_t tile = std::size_t(m_config.lanes) * m_config.itemsPerLane;
    std::size_t histogramEntries = (std::size_t(1) << m_config.digitBits) * divUp(count, tile);
    growBuffer(m_histograms, m_histogramCapacity, histogramEntries);
}

// Exclusive scan of `count` uints of buffer `data` in place. Levels above one block reduce each
// block to a sum (into m_scanLevels[level]), scan those sums recursively, and scan each block
// starting from its scanned sum.
void RadixSort::scan(GLuint data, std::size_t count, std::size_t level) {
    std::size_t blocks = divUp(count, kScanBlock);
    TC_CHECK_OP(blocks, <=, std::size_t(65535));
    if (blocks > 1) {
        if (m_scanLevels.size() <= level) m_scanLevels.resize(level + 1);
        ScanLevel& sums = m_scanLevels[level];
        growBuffer(sums.sums, sums.count, blocks);
        setUint(m_scanReduce, "count", count);
        glUseProgram(m_scanReduce.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kScanData, data);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kScanBlockSums, sums.sums.id());
        glDispatchCompute(static_cast<GLuint>(blocks), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        scan(sums.sums.id(), blocks, level + 1);
    }
    setUint(m_scan, "count", count);
    glProgramUniform1i(m_scan.id(), uniform(m_scan, "addBlockOffsets"), blocks > 1 ? 1 : 0);
    glUseProgram(m_scan.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kScanData, data);
    // The block sums binding must name a buffer even when the block offsets are not read.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kScanBlockSums,
                     blocks > 1 ? m_scanLevels[level].sums.id() : data);
    glDispatchCompute(static_cast<GLuint>(blocks), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void RadixSort::sort(const Buffer& keys, const Buffer& values, std::size_t count, int lowestBit) {
    TC_CHECK(lowestBit >= 0 && lowestBit < 32 && lowestBit % (2 * m_config.digitBits) == 0);
    if (count <= 1) return;  // already sorted; no GL work
    TC_CHECK_OP(bufferSize(keys), >=, count * sizeof(GLuint));
    TC_CHECK_OP(bufferSize(values), >=, count * sizeof(GLuint));
    TC_CHECK_OP(count, <=, std::size_t(0xFFFFFFFFu));
    ensureScratch(count);

    std::size_t tile = std::size_t(m_config.lanes) * m_config.itemsPerLane;
    std::size_t groups = divUp(count, tile);
    TC_CHECK_OP(groups, <=, std::size_t(65535));  // GL_MAX_COMPUTE_WORK_GROUP_COUNT minimum
    std::size_t histogramEntries = (std::size_t(1) << m_config.digitBits) * groups;
    for (const Program* program : {&m_histogram, &m_scatter}) {
        setUint(*program, "count", count);
        setUint(*program, "groupCount", groups);
    }

    GLuint keysA = keys.id(), valuesA = values.id();
    GLuint keysB = m_keysScratch.id(), valuesB = m_valuesScratch.id();
    for (int shift = lowestBit; shift < 32; shift += m_config.digitBits) {
        setUint(m_histogram, "shift", shift);
        setUint(m_scatter, "shift", shift);

        glUseProgram(m_histogram.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixKeysIn, keysA);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixHistograms, m_histograms.id());
        glDispatchCompute(static_cast<GLuint>(groups), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

        scan(m_histograms.id(), histogramEntries, 0);

        glUseProgram(m_scatter.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixKeysIn, keysA);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixValuesIn, valuesA);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixKeysOut, keysB);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixValuesOut, valuesB);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kRadixOffsets, m_histograms.id());
        glDispatchCompute(static_cast<GLuint>(groups), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

        std::swap(keysA, keysB);
        std::swap(valuesA, valuesB);
    }
    glUseProgram(0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT |
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

}  // namespace tc::gl
