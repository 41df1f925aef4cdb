# Warning and sanitizer flags applied through an interface target, so that
# every nbrdf target (library, CLI, tests, benches) is built the same way.
add_library(nbrdf_flags INTERFACE)
target_compile_options(nbrdf_flags INTERFACE
  $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra -Wshadow -Wstrict-prototypes -Wno-unused-parameter>
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wno-unused-parameter>)
# -ffp-contract=off: fused multiply-adds make results depend on the compiler's
# choices; the ground truth and the networks must give the same bits everywhere.
target_compile_options(nbrdf_flags INTERFACE -ffp-contract=off)
# POSIX and M_PI from the C library, with C11 itself kept strict.
target_compile_definitions(nbrdf_flags INTERFACE _DEFAULT_SOURCE)
if(NBRDF_WERROR)
  target_compile_options(nbrdf_flags INTERFACE -Werror)
endif()
if(NBRDF_SANITIZE)
  target_compile_options(nbrdf_flags INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(nbrdf_flags INTERFACE -fsanitize=address,undefined)
endif()
