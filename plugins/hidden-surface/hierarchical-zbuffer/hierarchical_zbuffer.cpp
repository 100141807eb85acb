// hierarchical-zbuffer: the z-buffer with a z-pyramid of Greene, Kass and Miller (SIGGRAPH 1993),
// exported as a plugin. The algorithm, its source and its code: hierarchical_zbuffer.hpp.
#include "hierarchical_zbuffer.hpp"

HSR_EXPORT_PLUGIN(hierarchical_zbuffer::HierarchicalZBuffer)
