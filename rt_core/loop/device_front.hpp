// kerf::rt::DeviceFront — a device that stands in front of the real one and passes its reads and
// writes on (LockstepWorldSync). When the loop installs a re-opened device it puts it behind the
// front (HapticLoop::keep_in_front) instead of replacing the front, so what the front adds to
// every read survives an unplug and re-open.
#pragma once

#include "firmware_host/device/device.hpp"

namespace kerf::rt {

class DeviceFront : public firmware_host::Device {
public:
    /// From the loop thread at a tick boundary: reads and writes go to `inner` from now on.
    /// @pre `inner` outlives its use here (the loop retires a device only after replacing it)
    virtual void set_inner(firmware_host::Device& inner) noexcept = 0;
    /// The device behind the front now.
    virtual firmware_host::Device& inner() noexcept = 0;
};

}  // namespace kerf::rt
