# The libraries redpost's core links, found once for every project that builds core/: the main
# build (CMakeLists.txt) and the standalone fuzz build (tests/fuzz/CMakeLists.txt). Every one is a
# Debian package that scripts/setup.sh installs.
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(tinyxml2 REQUIRED)
find_package(fmt REQUIRED)
find_package(NLopt 2.6 REQUIRED)  # placement optimisation (issue 8)
# Distances between bodies (issue 46, docs/collision.md). Its CMake package, not pkg-config,
# whose Cflags would force -std=c++11 on us.
find_package(fcl 0.7 REQUIRED)
find_package(Qhull 8.0 REQUIRED)  # the convex hull of a <convex> body's points (issue 46)
find_package(Threads REQUIRED)
