#pragma once
// Running a command line in a shell from a test, as a user would: the CLI tests
// (cli_test.cpp) and the MPI runs (mpi_render_test.cpp).

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace dynrt::test {

struct ShellRun {
    int exit_code;
    std::string output;  // stdout and stderr together
};

/// Runs `command_line` in a shell, stdout and stderr together.
inline ShellRun run_shell(const std::string& command_line) {
    const std::string command = command_line + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return {-1, "popen failed"};
    std::string output;
    std::array<char, 4096> buffer;
    while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
    const int status = pclose(pipe);
    // A signal (a crash) is reported as exit code 128 + signal, as a shell would.
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return {code, output};
}

}  // namespace dynrt::test
