#pragma once
// The command line: riffle run | check | resume. Returns the process exit code.
namespace riffle {
int cli_main(int argc, char** argv);
}
