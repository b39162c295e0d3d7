// tests/gl/quad_indices_test.cpp: the quad's flat id + 1 (0 stays "not drawn").
flat in uint vQuad;
layout(location = 0) out uint outQuad;

void main() { outQuad = vQuad + 1u; }
