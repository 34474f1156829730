# The Debian package: after a build, `cpack -G DEB` in the build folder makes
# raytracer_VERSION_ARCH.deb from the install rules (raytracer, raytracer-view and
# raytracer-view-headless, raytracer-mpi if it was built, the man pages and the example
# scenes), installed under /usr. dpkg-shlibdeps (package dpkg-dev) works out Depends from
# the libraries the programs load; without it the list below is used.
# scripts/package-test.sh builds the package, unpacks it into a scratch root and runs it.
set(CPACK_PACKAGE_NAME raytracer)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "ray tracer for raytracer2 scenes, with an interactive previewer")
set(CPACK_PACKAGE_DESCRIPTION "raytracer renders scenes in the raytracer2 text format (spheres, tetrahedra,
cylinders, tori, CSG, planes, glass and mirrors) to PPM or PNG. raytracer-view shows
a scene while it renders and edits its camera, materials and text; its headless twin
takes screenshots without a display.")
set(CPACK_PACKAGE_CONTACT "raytracer2 maintainers <maintainers@users.noreply.h-seed-bc7a95e8.example>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)

option(RAYTRACER_DEB_SHLIBDEPS "Work out the .deb's Depends with dpkg-shlibdeps when it is there" ON)
find_program(RAYTRACER_DPKG_SHLIBDEPS dpkg-shlibdeps)
find_program(RAYTRACER_FILE file)  # CPack's shlibdeps step needs it too
if(RAYTRACER_DEB_SHLIBDEPS AND RAYTRACER_DPKG_SHLIBDEPS AND RAYTRACER_FILE)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
else()
  # Debian 12's names for what the programs link, as dpkg-shlibdeps would find them.
  set(deps "libc6 (>= 2.34)" "libgcc-s1 (>= 3.0)" "libstdc++6 (>= 12)" "libstb0 (>= 0.0~git20180212.15.e6afb9c)"
      "libdeflate0 (>= 1.14)")
  if(TARGET raytracer-view)
    list(APPEND deps "libglfw3 (>= 3.3)" "libopengl0")
  endif()
  if(TARGET raytracer-view-headless)
    list(APPEND deps "libosmesa6 (>= 10.2~)")
  endif()
  if(TARGET raytracer-mpi)
    list(APPEND deps "libopenmpi3 (>= 4.1.4)")
  endif()
  list(JOIN deps ", " CPACK_DEBIAN_PACKAGE_DEPENDS)
  if(RAYTRACER_DEB_SHLIBDEPS)
    message(STATUS "dpkg-shlibdeps or file not found (Debian packages dpkg-dev, file): "
                   "the .deb gets a fixed Depends list")
  endif()
endif()

include(CPack)
