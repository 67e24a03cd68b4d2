// Issue 9, items 2 and 11: kerf-hapsim as a user runs it. A bad script (unknown fault, value out
// of range, a move outside the workspace) is file:line and exit 1 before anything listens; NaN on
// the command line is a usage error; an unwritable trace fails at start, not after the run.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;
using kerf::test::ProcessRun;

class HapsimInputs : public ::testing::Test {
protected:
    void SetUp() override {
        char tmpl[] = "/tmp/kerf-hapsim-inputs-XXXXXX";
        dir_ = mkdtemp(tmpl);
    }
    void TearDown() override { fs::remove_all(dir_); }
    ProcessRun hapsim(std::vector<std::string> args) {
        args.insert(args.begin(), {"--socket", (dir_ / "dev.sock").string()});
        return kerf::test::run_program(dir_, "kerf-hapsim", std::move(args),
                                       std::chrono::seconds(20));
    }
    std::string script(const std::string& text) {
        const fs::path p = dir_ / "hand.csv";
        std::ofstream(p) << "# test script\n" << text << "\n";
        return p.string();
    }
    fs::path dir_;
};

TEST_F(HapsimInputs, UnknownFaultNamesAndOutOfRangeValuesAreFileLineErrors) {
    for (const char* line : {"fault,estpo,on", "fault,delay,999999", "fault,drop,maybe"}) {
        const ProcessRun r = hapsim({"--script", script(line)});
        EXPECT_EQ(r.exit_code, 1) << line << ": " << r.err;
        EXPECT_NE(r.err.find("hand.csv:2"), std::string::npos) << line << ": " << r.err;
        EXPECT_EQ(r.out.find("ready"), std::string::npos) << r.out;
    }
}

TEST_F(HapsimInputs, AMoveOutsideTheWorkspaceIsAFileLineError) {
    const ProcessRun r = hapsim({"--script", script("move,10,0,0,1")});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("hand.csv:2: move reaches 10.0000 m on axis x, outside the workspace"),
              std::string::npos)
        << r.err;
}

TEST_F(HapsimInputs, NonFiniteNumbersOnTheCommandLineAreUsageErrors) {
    for (const char* option : {"--peak-force-n", "--resolution-m"}) {
        for (const char* value : {"nan", "inf", "-nan"}) {
            const ProcessRun r = hapsim({option, value});
            EXPECT_EQ(r.exit_code, 2) << option << " " << value << ": " << r.err;
            EXPECT_NE(r.err.find("not a finite number"), std::string::npos) << r.err;
        }
    }
}

TEST_F(HapsimInputs, AnUnwritableTraceFailsAtStartBeforeListening) {
    const ProcessRun r = hapsim({"--trace", (dir_ / "no-such-folder" / "trace.csv").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("cannot write trace"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("ready"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "dev.sock"));
}

}  // namespace
