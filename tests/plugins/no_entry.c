/* A shared library that is not an hsr plugin: it lacks the entry symbol. */
#include "hsr/abi.h"

HSR_EXPORT int not_an_hsr_plugin(void) { return 42; }
