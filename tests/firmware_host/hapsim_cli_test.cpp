// kerf-hapsim's command line: every bad argument is a clear error with the right exit code.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "firmware_host/transport/seqpacket_socket.hpp"
#include "tests/firmware_host/hapsim_process.hpp"

namespace kerf::firmware_host {
namespace {

std::string run(const std::string& args, int& exit_code) {
    const std::string cmd = std::string(KERF_BIN_DIR) + "/kerf-hapsim " + args + " 2>&1 </dev/null";
    std::string out;
    FILE* p = ::popen(cmd.c_str(), "r");
    char buf[512];
    while (p != nullptr && std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
    const int status = p != nullptr ? ::pclose(p) : -1;
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

TEST(HapsimCli, UsageErrorsExitTwoAndNameTheOption) {
    int rc = 0;
    auto out = run("--protocol usb --socket /tmp/x.sock", rc);
    EXPECT_EQ(rc, 2);
    EXPECT_NE(out.find("--protocol"), std::string::npos) << out;
    out = run("--protocol kerf", rc);
    EXPECT_EQ(rc, 2);
    EXPECT_NE(out.find("--socket"), std::string::npos) << out;
    out = run("--socket /tmp/x.sock --period-us 5", rc);
    EXPECT_EQ(rc, 2);
    out = run("--socket /tmp/x.sock --serial " + std::string(20, 'A'), rc);
    EXPECT_EQ(rc, 2);
    EXPECT_NE(out.find("at most 16"), std::string::npos) << out;
}

TEST(HapsimCli, ABadScriptExitsOneWithFileAndLine) {
    const std::string script = test::temp_path("bad.csv");
    std::ofstream(script) << "move,0,0,0,1\nhold,soon\n";
    int rc = 0;
    const auto out = run("--socket " + test::temp_path("s.sock") + " --script " + script, rc);
    EXPECT_EQ(rc, 1);
    EXPECT_NE(out.find(script + ":2: hold: value 1 'soon' is not a finite number"),
              std::string::npos)
        << out;
}

TEST(HapsimCli, ASocketPathInTheWayIsAClearError) {
    const std::string path = test::temp_path("not-a-socket");
    std::ofstream(path) << "x";
    int rc = 0;
    const auto out = run("--socket " + path, rc);
    EXPECT_EQ(rc, 1);
    EXPECT_NE(out.find("a file that is not a socket is in the way"), std::string::npos) << out;
    std::remove(path.c_str());
}

// Issue 9, item 11: a second kerf-hapsim on the socket a live one listens on is refused (it used
// to unlink the socket and take it over); a stale socket nobody listens on is replaced.
TEST(HapsimCli, ALiveListenersSocketIsNeverTakenOverButAStaleOneIsReplaced) {
    test::HapsimProcess first({});
    ASSERT_TRUE(first.ready()) << first.output();
    int rc = 0;
    std::string out = run("--socket " + first.socket_path() + " --commands", rc);
    EXPECT_EQ(rc, 1) << out;
    EXPECT_NE(out.find(first.socket_path()), std::string::npos) << out;
    EXPECT_NE(out.find("another process is listening on this socket"), std::string::npos) << out;
    EXPECT_EQ(out.find("ready"), std::string::npos) << out;
    EXPECT_TRUE(first.command("status")) << first.output();  // the first still serves...
    auto host = SeqpacketSocket::connect(first.socket_path());
    EXPECT_TRUE(host) << host.error().message();  // ...on its own socket
    EXPECT_EQ(first.stop(), 0);

    // Stale: bound, then its owner died without removing it.
    const std::string stale = test::temp_path("stale.sock");
    {
        const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", stale.c_str());
        ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
        ::close(fd);
    }
    out = run("--socket " + stale + " --commands", rc);  // stdin at EOF: quits once ready
    EXPECT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("ready"), std::string::npos) << out;
}

TEST(HapsimCli, ABadProfileExitsOneAndNamesTheFile) {
    const std::string profile = test::temp_path("bad-profile.toml");
    std::ofstream(profile) << "name = 3\n";
    int rc = 0;
    const auto out = run("--socket " + test::temp_path("s.sock") + " --profile " + profile, rc);
    EXPECT_EQ(rc, 1);
    EXPECT_NE(out.find("kerf-hapsim: profile: " + profile), std::string::npos) << out;
}

TEST(HapsimCli, AnUnknownFaultCommandIsRefusedAndTheEmulatorKeepsRunning) {
    test::HapsimProcess sim({"--protocol", "kerf"});
    ASSERT_TRUE(sim.ready());
    EXPECT_FALSE(sim.command("fault meteor on"));
    EXPECT_NE(sim.output().find("unknown fault 'meteor'"), std::string::npos) << sim.output();
    EXPECT_TRUE(sim.command("fault drop on"));
    EXPECT_EQ(sim.stop(), 0);
}

}  // namespace
}  // namespace kerf::firmware_host
