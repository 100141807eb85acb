// A plugin that reaches for a host header. It must not compile: in-tree plugins are built against
// hsr::sdk alone, whose include path holds only the SDK (ctest plugin_cannot_include_host_header).
#include <hsr/sdk.hpp>
#include <hsr/scene.hpp>
