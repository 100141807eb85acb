// The hierarchical-zbuffer plugin's drawing with steps (render_steps), compiled apart from render()'s
// so that instantiating it cannot change how the compiler inlines the plain drawing.
#include "hierarchical_zbuffer.hpp"

template class hsr::sdk::StepsDrawing<hierarchical_zbuffer::HierarchicalZBuffer>;
