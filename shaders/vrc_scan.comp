// Exclusive prefix sum of data[0..uCount) in place, total in data[uCount], by one workgroup: each
// invocation sums a contiguous chunk, the chunk sums are scanned in shared memory, then each
// invocation writes its chunk's prefixes. For the per-polyline piece counts of the VRC GPU build
// (tens of thousands of entries: one dispatch, no multi-level scan needed).
layout(local_size_x = 256) in;
layout(std430, binding = SSBO_VRC_COUNTS) buffer Data { uint data[]; };
uniform uint uCount;

shared uint chunkSums[256];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint chunk = (uCount + 255u) / 256u;
    uint begin = min(lane * chunk, uCount), end = min(begin + chunk, uCount);
    uint sum = 0u;
    for (uint i = begin; i < end; ++i) sum += data[i];
    chunkSums[lane] = sum;
    barrier();
    // Hillis-Steele inclusive scan of the 256 chunk sums.
    for (uint offset = 1u; offset < 256u; offset <<= 1u) {
        uint add = lane >= offset ? chunkSums[lane - offset] : 0u;
        barrier();
        chunkSums[lane] += add;
        barrier();
    }
    uint running = chunkSums[lane] - sum;  // exclusive
    for (uint i = begin; i < end; ++i) {
        uint value = data[i];
        data[i] = running;
        running += value;
    }
    if (lane == 255u) data[uCount] = chunkSums[255];
}
