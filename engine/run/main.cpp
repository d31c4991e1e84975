#include "engine/run/cli.hpp"

int main(int argc, char** argv) { return riffle::cli_main(argc, argv); }
