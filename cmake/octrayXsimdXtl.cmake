# octrayXsimdXtl.cmake — make the `xsimd` target linkable when xtl is absent.
#
# Debian's libxsimd-dev 8.1.0 exports INTERFACE_LINK_LIBRARIES "xtl" on the
# imported `xsimd` target, but its xsimdConfig.cmake never looks for xtl, so
# without an `xtl` target the name falls through to the linker as `-lxtl` and
# every executable that links xsimd (octray::octray's public dependency) fails
# with "cannot find -lxtl". octray uses no xtl feature. If the xsimd target
# asks for xtl and no `xtl` target exists: use a real xtl package when one is
# installed, otherwise define `xtl` as an empty interface target. Included by
# octray's top-level CMakeLists.txt and by the installed octrayConfig.cmake,
# after xsimd has been found; it does nothing with a self-consistent xsimd.
if(TARGET xsimd AND NOT TARGET xtl)
  get_target_property(_octray_xsimd_deps xsimd INTERFACE_LINK_LIBRARIES)
  if(_octray_xsimd_deps AND "xtl" IN_LIST _octray_xsimd_deps)
    find_package(xtl QUIET CONFIG)
    if(NOT TARGET xtl)
      add_library(xtl INTERFACE IMPORTED)
    endif()
  endif()
  unset(_octray_xsimd_deps)
endif()
