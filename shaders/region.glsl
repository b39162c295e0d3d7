// Data-parallel rendering: the region box of core/region.h, the GPU twin of RegionBox::contains
// (same comparisons, so CPU and GPU assign a point to the same region).
// A region draws a tube or sphere only where the ray ENTERS it inside the box: the regions'
// images, composited in view order, are then the whole frame's. Programs that clip are compiled
// with REGION_CLIP; without it the chunk declares nothing and the shaders pay nothing (the box is
// fixed when a technique is made, so a variant costs one compile, where a uniform flag would cost
// a test per fragment of every frame). GLSL 4.50 chunk, #include'd after frame_uniforms.glsl.
#ifndef TC_REGION_GLSL
#define TC_REGION_GLSL

#ifdef REGION_CLIP
// Half-open [uRegionLo, uRegionHi) per axis; the faces may be infinite.
bool inRegion(vec3 p) {
    return p.x >= uRegionLo.x && p.x < uRegionHi.x && p.y >= uRegionLo.y && p.y < uRegionHi.y &&
           p.z >= uRegionLo.z && p.z < uRegionHi.z;
}
#endif

#endif  // TC_REGION_GLSL
