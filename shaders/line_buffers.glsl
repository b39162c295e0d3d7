// The line set as the renderer uploads it (gl/rounded_cone_renderer.cpp): per-vertex data never
// moves; segment S joins vertices segmentVertices[2S] and [2S + 1]. GLSL 4.50 chunk.
layout(std430, binding = 0) readonly buffer PositionRadius { vec4 positionRadius[]; };
layout(std430, binding = 1) readonly buffer Colors { vec4 vertexColor[]; };
layout(std430, binding = 2) readonly buffer PolylineIds { uint polylineId[]; };
layout(std430, binding = 3) readonly buffer SegmentVertices { uint segmentVertices[]; };
