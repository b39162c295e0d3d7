#pragma once
// The published 256-entry sRGB tables behind the built-in colormaps (see colormap_tables.cpp for
// their sources and licences). Entry i is the colour at t = i / 255.
namespace tc::colormap_tables {

extern const float Viridis[256][3];
extern const float Magma[256][3];
extern const float Inferno[256][3];
extern const float Plasma[256][3];
extern const float Turbo[256][3];

}  // namespace tc::colormap_tables
