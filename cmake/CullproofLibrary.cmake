# cullproof_library(<name> [COMPONENT <component>] SOURCES <files...>
#                   [PUBLIC <targets...>] [PRIVATE <targets...>])
# One library target per folder: cullproof_<name> (alias and export name cullproof::<name>), built
# from the folder's sources. Its public headers are the folder's include/cullproof/<name>/, and
# that is the only include directory it gives its consumers: a private header stays beside its
# .cpp, out of every other target's reach. With a COMPONENT it is installed and exported in that
# component's export set (find_package(cullproof COMPONENTS <component>)); without one it is a
# part of the program only. docs/architecture.md's table of libraries is checked against every
# call (cmake/CheckArchitecture.cmake).
function(cullproof_library name)
  cmake_parse_arguments(L "" "COMPONENT" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  if(L_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "cullproof_library(${name}): unknown arguments ${L_UNPARSED_ARGUMENTS}")
  endif()
  set(t cullproof_${name})
  add_library(${t} ${L_SOURCES})
  add_library(cullproof::${name} ALIAS ${t})
  # While the major version is 0, a minor version may break the ABI (the package's version file
  # says SameMinorVersion), so the SOVERSION carries both.
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${t}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_compile_features(${t} PUBLIC cxx_std_17)
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include/cullproof/${name})
    target_include_directories(${t} PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  endif()
  target_link_libraries(${t} PUBLIC ${L_PUBLIC} PRIVATE ${L_PRIVATE})
  # The project's warnings and floating-point flags as the target's own options, not as a link to
  # cullproof_build_flags: a static library's private links are exported, and the flags are not.
  target_compile_options(${t} PRIVATE $<TARGET_PROPERTY:cullproof_build_flags,INTERFACE_COMPILE_OPTIONS>)
  target_link_options(${t} PRIVATE $<TARGET_PROPERTY:cullproof_build_flags,INTERFACE_LINK_OPTIONS>)
  set_property(GLOBAL APPEND PROPERTY CULLPROOF_LIBRARIES ${name})
  set_target_properties(${t} PROPERTIES CULLPROOF_FOLDER ${CMAKE_CURRENT_SOURCE_DIR}
    CULLPROOF_COMPONENT "${L_COMPONENT}")
  if(L_COMPONENT)
    set_property(GLOBAL APPEND PROPERTY CULLPROOF_COMPONENTS ${L_COMPONENT})
    if(CULLPROOF_INSTALL)
      install(TARGETS ${t} EXPORT cullproof_${L_COMPONENT}_targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
      if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include/cullproof/${name})
        install(DIRECTORY include/cullproof/${name} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cullproof)
      endif()
    endif()
  endif()
endfunction()

# cullproof_optional(<part> <found> <what is missing>)
# An optional part (the oracle, the harness, the program, the engines, the benchmarks, the page
# scripts, the tests) is built when what it needs is found and skipped with a message when it is
# not. CULLPROOF_REQUIRE_ALL turns a skip into an error (the test suite sets it: a part skipped
# would leave its tests out unseen). Sets CULLPROOF_SKIPPED in the parent scope.
function(cullproof_optional part found missing)
  if(NOT found)
    if(CULLPROOF_REQUIRE_ALL)
      message(FATAL_ERROR "cullproof: ${part} needs ${missing} (CULLPROOF_REQUIRE_ALL is on)")
    endif()
    message(STATUS "cullproof: skipping ${part}: ${missing} not found")
    set_property(GLOBAL APPEND PROPERTY CULLPROOF_SKIPPED "${part}")
  endif()
endfunction()
