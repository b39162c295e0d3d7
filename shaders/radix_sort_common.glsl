// Shared by the radix sort passes (gl/radix_sort.h). Defines set by RadixSort::create():
//   RADIX_BITS            digit width (4 or 8); RADIX_SIZE = 2^RADIX_BITS digit values
//   RADIX_LANES           invocations per workgroup (local_size_x)
//   RADIX_ITEMS_PER_LANE  consecutive keys each invocation handles
// A workgroup owns the tile [group * RADIX_TILE, +RADIX_TILE) of the input; invocation `lane`
// owns the contiguous run [lane * RADIX_ITEMS_PER_LANE, +RADIX_ITEMS_PER_LANE) of the tile and
// walks it in order. That is what makes the scatter stable without subgroup operations: the rank
// of a key among equal digits of its tile is (keys of that digit in earlier lanes' runs) + (keys
// of that digit seen earlier in its own run). It also suits llvmpipe, which runs a workgroup on
// one CPU thread with the lanes in SIMD registers: each lane streams through memory sequentially.
//   keys_(i)              the including pass's key buffer access, defined before the include
#define RADIX_SIZE (1u << RADIX_BITS)
#define RADIX_TILE (RADIX_LANES * RADIX_ITEMS_PER_LANE)

uniform uint count;       // keys to sort
uniform uint shift;       // bit offset of this pass's digit
uniform uint groupCount;  // workgroups of the histogram and scatter passes

// Per-lane digit counters, digit-major: radixCounts[digit * RADIX_LANES + lane].
shared uint radixCounts[RADIX_SIZE * RADIX_LANES];

uint radixDigit(uint key)
{
    return (key >> shift) & (RADIX_SIZE - 1u);
}

// The run of the calling lane, clamped to `count`: [begin, end).
void radixLaneRun(out uint begin, out uint end)
{
    uint tileBegin = gl_WorkGroupID.x * RADIX_TILE;
    begin = min(tileBegin + gl_LocalInvocationID.x * RADIX_ITEMS_PER_LANE, count);
    end = min(begin + RADIX_ITEMS_PER_LANE, count);
}

// Counts the digits of the calling lane's run into a private array. On llvmpipe a private array
// is much cheaper to index per lane than shared memory (measured: 2.3x faster histograms).
void radixCountLaneRun(out uint counts[RADIX_SIZE])
{
    for (uint d = 0u; d < RADIX_SIZE; ++d)
        counts[d] = 0u;
    uint begin, end;
    radixLaneRun(begin, end);
    for (uint i = begin; i < end; ++i)
        ++counts[radixDigit(keys_(i))];
}

// Copies the calling lane's counts to radixCounts. Callers need a barrier() before reading
// other lanes' counts.
void radixPublishLaneCounts(uint counts[RADIX_SIZE])
{
    uint lane = gl_LocalInvocationID.x;
    for (uint d = 0u; d < RADIX_SIZE; ++d)
        radixCounts[d * RADIX_LANES + lane] = counts[d];
}
