// Multi-level exclusive scan of uints for the radix sort (gl/radix_sort.cpp drives the levels).
// A workgroup owns a block of SCAN_LANES * SCAN_ITEMS_PER_LANE values; each lane a contiguous run
// of it, summed serially (work-efficient, and sequential memory access on llvmpipe), then the
// lane sums are scanned in shared memory.
//   RADIX_SCAN_REDUCE defined: blockSums[group] = sum of the block (the level below scans those).
//   otherwise: data[] is replaced in place by its exclusive scan within the block, plus
//              blockSums[group] if addBlockOffsets (the scanned sums of the level below).
layout(local_size_x = SCAN_LANES) in;

layout(std430, binding = SSBO_SCAN_DATA) buffer Data { uint data[]; };
layout(std430, binding = SSBO_SCAN_BLOCK_SUMS) buffer BlockSums { uint blockSums[]; };

uniform uint count;
uniform bool addBlockOffsets;

shared uint laneSums[SCAN_LANES];

void main()
{
    uint lane = gl_LocalInvocationID.x;
    uint blockBegin = gl_WorkGroupID.x * (SCAN_LANES * SCAN_ITEMS_PER_LANE);
    uint begin = min(blockBegin + lane * SCAN_ITEMS_PER_LANE, count);
    uint end = min(begin + SCAN_ITEMS_PER_LANE, count);
    uint sum = 0u;
    for (uint i = begin; i < end; ++i)
        sum += data[i];
    laneSums[lane] = sum;
    barrier();
#ifdef RADIX_SCAN_REDUCE
    if (lane == 0u) {
        uint total = 0u;
        for (uint l = 0u; l < SCAN_LANES; ++l)
            total += laneSums[l];
        blockSums[gl_WorkGroupID.x] = total;
    }
#else
    // SCAN_LANES is small (64): one lane scanning serially beats log-step scans with a barrier
    // each, which on llvmpipe cost a coroutine switch of every lane.
    if (lane == 0u) {
        uint running = addBlockOffsets ? blockSums[gl_WorkGroupID.x] : 0u;
        for (uint l = 0u; l < SCAN_LANES; ++l) {
            uint s = laneSums[l];
            laneSums[l] = running;
            running += s;
        }
    }
    barrier();
    uint running = laneSums[lane];
    for (uint i = begin; i < end; ++i) {
        uint v = data[i];
        data[i] = running;
        running += v;
    }
#endif
}
