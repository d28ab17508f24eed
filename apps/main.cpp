#include "apps/cli.h"

int main(int argc, char** argv) { return aquaform::cli::run_main(argc, argv); }
