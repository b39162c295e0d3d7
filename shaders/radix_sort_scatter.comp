// Radix sort pass 3 of 3: stable scatter. Each lane recounts its run (cheaper than storing
// per-lane histograms globally), the counters become per-lane output positions — the scanned
// global offset of (digit, group) plus the keys of that digit in earlier lanes — and each lane
// then walks its run in order, writing every key and value to the next position of its digit.
layout(local_size_x = RADIX_LANES) in;

layout(std430, binding = SSBO_RADIX_KEYS_IN) readonly buffer KeysIn { uint keysIn[]; };
layout(std430, binding = SSBO_RADIX_VALUES_IN) readonly buffer ValuesIn { uint valuesIn[]; };
layout(std430, binding = SSBO_RADIX_KEYS_OUT) writeonly buffer KeysOut { uint keysOut[]; };
layout(std430, binding = SSBO_RADIX_VALUES_OUT) writeonly buffer ValuesOut { uint valuesOut[]; };
layout(std430, binding = SSBO_RADIX_OFFSETS) readonly buffer Offsets { uint offsets[]; };  // scanned histograms

#define keys_(i) keysIn[i]
#include "radix_sort_common.glsl"

void main()
{
    uint lane = gl_LocalInvocationID.x;
    uint positions[RADIX_SIZE];
    radixCountLaneRun(positions);
    radixPublishLaneCounts(positions);
    barrier();
    for (uint d = lane; d < RADIX_SIZE; d += RADIX_LANES) {
        uint position = offsets[d * groupCount + gl_WorkGroupID.x];
        for (uint l = 0u; l < RADIX_LANES; ++l) {
            uint c = radixCounts[d * RADIX_LANES + l];
            radixCounts[d * RADIX_LANES + l] = position;
            position += c;
        }
    }
    barrier();
    for (uint d = 0u; d < RADIX_SIZE; ++d)
        positions[d] = radixCounts[d * RADIX_LANES + lane];
    uint begin, end;
    radixLaneRun(begin, end);
    for (uint i = begin; i < end; ++i) {
        uint key = keysIn[i];
        uint digit = radixDigit(key);
        uint position = positions[digit];
        positions[digit] = position + 1u;
        keysOut[position] = key;
        valuesOut[position] = valuesIn[i];
    }
}
