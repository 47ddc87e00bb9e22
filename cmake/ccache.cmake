# Compiler cache (VID_CCACHE, default ON when ccache is installed; scripts/setup.sh installs it).
#
# One checkout builds the C++ libraries twice: scripts/build.sh into build/ (programs, tests,
# the in-tree Python module) and scripts/setup.sh's wheel of the Python package into build-py/
# (pip, scikit-build-core; issue #52). Both compile the same sources with the same flags, so a
# cache shared by the two makes the second build cost its links only. The cache lives in the
# checkout (.ccache/, git-ignored) and paths are rewritten relative to the checkout
# (CCACHE_BASEDIR), which makes the objects of build/ and build-py/ (both one level below the
# root) hit each other. A clean clone starts with an empty cache: nothing is reused across clones.
find_program(VID_CCACHE_PROGRAM ccache)
option(VID_CCACHE "Compile through ccache (cache in <source>/.ccache)" ON)
if(VID_CCACHE AND VID_CCACHE_PROGRAM)
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
      CCACHE_DIR=${PROJECT_SOURCE_DIR}/.ccache ${VID_CCACHE_PROGRAM})
  message(STATUS "ccache: ${VID_CCACHE_PROGRAM} (cache ${PROJECT_SOURCE_DIR}/.ccache)")
endif()
