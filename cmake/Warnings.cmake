# gmotion_warnings: an INTERFACE target that carries the project's warning flags (not exported).
add_library(gmotion_warnings INTERFACE)
target_compile_options(gmotion_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wimplicit-fallthrough -Wmissing-declarations
  $<$<BOOL:${GMOTION_WERROR}>:-Werror>)
