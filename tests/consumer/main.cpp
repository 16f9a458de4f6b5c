/// @file consumer SYSTEM_FILE: prints the package version, the system's name, its map count and
/// each map's contraction factor, through the installed headers and library only.
#include <cstdio>
#include <exception>

#include "ifsforge/io/system_file.h"
#include "ifsforge/model/ifs.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer SYSTEM_FILE\n");
    return 2;
  }
  try {
    const ifsforge::Ifs system = ifsforge::load_system(argv[1]);
    std::printf("version %s\n", IFSFORGE_PACKAGE_VERSION);
    std::printf("name %s\n", system.name().c_str());
    std::printf("maps %zu\n", system.size());
    std::printf("contraction");
    for (double s : system.contraction_factors()) std::printf(" %.6f", s);
    std::printf("\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
