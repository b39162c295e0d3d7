// The line set as the renderer uploads it (gl/rounded_cone_renderer.cpp): per-vertex data never
// moves; segment S joins vertices segmentVertices[2S] and [2S + 1]. GLSL 4.50 chunk.
layout(std430, binding = SSBO_POSITION_RADIUS) readonly buffer PositionRadius { vec4 positionRadius[]; };
layout(std430, binding = SSBO_VERTEX_COLORS) readonly buffer Colors { vec4 vertexColor[]; };
layout(std430, binding = SSBO_POLYLINE_IDS) readonly buffer PolylineIds { uint polylineId[]; };
layout(std430, binding = SSBO_SEGMENT_VERTICES) readonly buffer SegmentVertices { uint segmentVertices[]; };
layout(std430, binding = SSBO_VERTEX_FLAGS) readonly buffer VertexFlags { uint vertexFlags[]; };  // VertexFlag bits
#ifdef DRAW_ORDER
// Draw slot -> segment id, front to back (the visibility sort of Groß & Gumhold 2020, Sect. 4.1).
layout(std430, binding = SSBO_DRAW_ORDER) readonly buffer DrawOrder { uint drawOrder[]; };
uint segmentOfSlot(uint slot) { return drawOrder[slot]; }
#else
uint segmentOfSlot(uint slot) { return slot; }
#endif
