// Rasterization only: counts the particle billboards' fragments (GL_SAMPLES_PASSED, no depth
// test), the total the early-z chunks' skipped-fragment count is measured against.
void main() {}
