#include "hoidslam/core/interrupt.h"

#include <csignal>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::core {
namespace {

TEST(InterruptGuard, TurnsSigtermIntoARequestAndRestoresTheHandler) {
  {
    InterruptGuard guard;
    EXPECT_FALSE(guard.requested());
    std::raise(SIGTERM);  // would end the test program without the guard
    EXPECT_TRUE(guard.requested());
    EXPECT_EQ(guard.signal(), SIGTERM);
  }
  EXPECT_EQ(std::signal(SIGTERM, SIG_DFL), SIG_DFL);
}

TEST(InterruptGuard, ANewGuardStartsWithoutARequest) {
  {
    InterruptGuard guard;
    std::raise(SIGINT);
  }
  InterruptGuard guard;
  EXPECT_FALSE(guard.requested());
}

TEST(InterruptGuard, ReraiseWithoutASignalThrows) {
  InterruptGuard guard;
  EXPECT_THROW(guard.Reraise(), Error);
}

}  // namespace
}  // namespace hoidslam::core
