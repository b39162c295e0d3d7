// Radix sort pass 1 of 3: the digit histogram of each workgroup's tile, written digit-major
// (histograms[digit * groupCount + group]) so one exclusive scan over the whole array gives each
// (digit, group) its first output position.
layout(local_size_x = RADIX_LANES) in;

layout(std430, binding = SSBO_RADIX_KEYS_IN) readonly buffer Keys { uint keys[]; };
layout(std430, binding = SSBO_RADIX_HISTOGRAMS) writeonly buffer Histograms { uint histograms[]; };

#define keys_(i) keys[i]
#include "radix_sort_common.glsl"

void main()
{
    uint counts[RADIX_SIZE];
    radixCountLaneRun(counts);
    radixPublishLaneCounts(counts);
    barrier();
    uint lane = gl_LocalInvocationID.x;
    for (uint d = lane; d < RADIX_SIZE; d += RADIX_LANES) {
        uint sum = 0u;
        for (uint l = 0u; l < RADIX_LANES; ++l)
            sum += radixCounts[d * RADIX_LANES + l];
        histograms[d * groupCount + gl_WorkGroupID.x] = sum;
    }
}
