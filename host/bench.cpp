// hsr bench (being written).
#include "commands.hpp"

int hsr::host::run_bench(const std::vector<std::string>&) { throw hsr::Error("bench: not built yet"); }
