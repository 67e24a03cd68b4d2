// Every module's error has the one shape (kerf::Error<Code>, config/base/error.hpp): a code enum
// whose to_string() returns std::string_view, where and what, printed "<where>: <what> (<code>)".
// A module added to the error vocabulary gets a line here; tests/module_rules/check_error_shape
// greps the tree so no other shape comes back.
#include <gtest/gtest.h>

#include <cerrno>
#include <string>
#include <type_traits>

#include "config/base/error.hpp"
#include "config/file_io/file_io.hpp"
#include "firmware_host/falcon/firmware_loader.hpp"
#include "firmware_host/transport/transport_error.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "tools/hapsim/hand_script.hpp"
#include "tools/supervise/child_process.hpp"

namespace kerf {
namespace {

template <class E>
constexpr bool kIsKerfError = requires(const E& e) {
    {e.code};
    requires ErrorCode<std::remove_cvref_t<decltype(e.code)>>;
    requires std::is_base_of_v<Error<std::remove_cvref_t<decltype(e.code)>>, E>;
};

static_assert(kIsKerfError<ipc::IpcError>);
static_assert(kIsKerfError<files::FileError>);
static_assert(kIsKerfError<firmware_host::TransportError>);
static_assert(kIsKerfError<firmware_host::falcon::FirmwareError>);
static_assert(kIsKerfError<hapsim::ScriptError>);
static_assert(kIsKerfError<supervise::SpawnError>);

/// The printed form of `e`, checked against the one formatter.
template <class E>
void expect_one_shape(const E& e, const std::string& printed) {
    EXPECT_EQ(e.message(), printed);
    EXPECT_EQ(e.message(), format_error(e.where, e.what, to_string(e.code)));
}

TEST(ErrorShape, Ipc) {
    expect_one_shape(ipc::IpcError{ipc::IpcErrc::kBadHeader, "segment demo", "magic 0x1234"},
                     "segment demo: magic 0x1234 (bad_header)");
    const ipc::IpcError os = ipc::os_error("segment demo", "mmap", ENOMEM);
    EXPECT_EQ(os.code, ipc::IpcErrc::kOsError);
    EXPECT_EQ(os.message().rfind("segment demo: mmap: ", 0), 0u) << os.message();
    EXPECT_EQ(os.message().substr(os.message().size() - 11), " (os_error)");
}

TEST(ErrorShape, FirmwareHost) {
    using firmware_host::TransportErrc;
    expect_one_shape(firmware_host::transport_error(TransportErrc::kNotConnected, "usb 0403:cb48",
                                                    "open USB device", "no such device connected"),
                     "usb 0403:cb48: open USB device: no such device connected (not_connected)");
    using firmware_host::falcon::FirmwareErrc;
    const auto e = firmware_host::falcon::firmware_error(FirmwareErrc::kEchoMismatch, "novint.bin",
                                                         124, firmware_host::LinkStatus::kOk, 3);
    expect_one_shape(e,
                     "novint.bin: firmware chunk echoed back different bytes: at image offset 124 "
                     "(after 3 load attempts) (echo_mismatch)");
    EXPECT_EQ(e.offset, 124u);
    EXPECT_EQ(e.attempts, 3);
}

TEST(ErrorShape, HapsimScript) {
    auto s = hapsim::parse_hand_script("hold,0.1\nwave,1\n", "hand.csv");
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().line, 2);
    EXPECT_EQ(s.error().where, "hand.csv:2");
    expect_one_shape(s.error(), "hand.csv:2: " + s.error().what + " (bad_line)");
}

TEST(ErrorShape, Files) {
    const auto r = files::read_regular_file("/nonexistent/kerf-shape.stl", 10);
    ASSERT_FALSE(r);
    expect_one_shape(r.error(), "/nonexistent/kerf-shape.stl: no such file (not_found)");
}

TEST(ErrorShape, Supervise) {
    expect_one_shape(
        supervise::SpawnError{supervise::SpawnErrc::kLogFile, "kerf-rt", "log: EACCES"},
        "kerf-rt: log: EACCES (log_file)");
}

}  // namespace
}  // namespace kerf
