// Test chunk for tests/gl/shader_library_test.cpp: the value test_fill.comp writes at index i.
// FILL_OFFSET comes from a define; FILL_SQUARE (a flag define) switches to i * i.
#ifndef FILL_OFFSET
#error "FILL_OFFSET must be defined"
#endif

uint fillValue(uint i)
{
#ifdef FILL_SQUARE
    return i * i + uint(FILL_OFFSET);
#else
    return 3u * i + uint(FILL_OFFSET);
#endif
}
