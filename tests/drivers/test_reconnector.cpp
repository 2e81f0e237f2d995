// Reconnector: the retry timer, backoff and liveness token the serial and Gazepoint drivers share.
// A real io_context with millisecond delays; the asserts are on counts and order, not on how long
// the (noisy, shared) machine took.
#include "fovea/drivers/reconnector.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <vector>

#include <boost/asio/io_context.hpp>

namespace {

using fovea::drivers::Reconnector;
using namespace std::chrono_literals;

TEST(Reconnector, StartConnectsAtOnceAndRetriesOnlyWhenAsked) {
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    int calls = 0;
    r.start(io, [&] { ++calls; });
    EXPECT_EQ(calls, 1);  // the first attempt, before the loop runs
    io.run();             // nothing pending: the attempt "worked"
    EXPECT_EQ(calls, 1);
}

TEST(Reconnector, DelayDoublesFromMinToMaxAndResetsAfterAConnect) {
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    std::vector<std::chrono::milliseconds> waits;  // what each retry was scheduled to wait
    int calls = 0;
    const auto t0 = std::chrono::steady_clock::now();
    r.start(io, [&] {
        ++calls;
        if (calls == 6) r.reset_delay();  // this attempt worked; then the link drops at once
        if (calls == 8) return;
        waits.push_back(r.next_delay());
        r.retry_later();
    });
    io.run();
    EXPECT_EQ(calls, 8);
    EXPECT_EQ(waits, (std::vector<std::chrono::milliseconds>{1ms, 2ms, 4ms, 8ms, 8ms, 1ms, 2ms}));
    // A timer never fires early: a lower bound only, which a slow machine cannot break.
    EXPECT_GE(std::chrono::steady_clock::now() - t0, 26ms);
}

TEST(Reconnector, ARetryReplacesAPendingOne) {
    boost::asio::io_context io;
    Reconnector r(1ms, 100ms);
    int calls = 0;
    r.start(io, [&] { ++calls; });
    r.retry_later();
    r.retry_later();
    EXPECT_EQ(r.next_delay(), 4ms);  // both doubled the delay
    io.run();
    EXPECT_EQ(calls, 2);  // the first attempt and one retry
}

TEST(Reconnector, StopCancelsAPendingRetry) {
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    int calls = 0;
    r.start(io, [&] { ++calls; });
    r.retry_later();
    r.stop();
    r.retry_later();  // after stop: nothing
    io.run();         // returns: no wait is left
    EXPECT_EQ(calls, 1);
    r.stop();  // idempotent
}

TEST(Reconnector, StopInsideTheCallbackEndsTheLoop) {
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    int calls = 0;
    r.start(io, [&] {
        ++calls;
        r.retry_later();  // the attempt failed ...
        if (calls == 2) {
            r.stop();  // ... and the driver closes in the same handler (a retry's)
            r.retry_later();
        }
    });
    io.run();
    EXPECT_EQ(calls, 2);
    EXPECT_TRUE(r.token().expired());
}

TEST(Reconnector, StopInsideTheFirstAttempt) {
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    int calls = 0;
    r.start(io, [&] {
        ++calls;
        r.retry_later();
        r.stop();
    });
    io.run();
    EXPECT_EQ(calls, 1);
}

TEST(Reconnector, RestartInsideTheCallbackKeepsGoing) {
    // close() and open() from inside a retry: the running callback is replaced while it runs.
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    std::vector<int> order;
    r.start(io, [&] {
        order.push_back(1);
        if (order.size() == 1) {
            r.retry_later();
            r.retry_later();
            return;
        }
        r.start(io, [&] {
            order.push_back(2);
            if (order.size() == 3) r.retry_later();
        });
        EXPECT_EQ(r.next_delay(), 2ms);  // the new session began at 1 ms, doubled once
    });
    io.run();
    EXPECT_EQ(order, (std::vector<int>{1, 1, 2, 2}));
}

TEST(Reconnector, DestructionWithARetryPendingIsSafe) {
    boost::asio::io_context io;
    int calls = 0;
    auto r = std::make_unique<Reconnector>(1ms, 8ms);
    r->start(io, [&] { ++calls; });
    r->retry_later();
    const auto token = r->token();
    r.reset();
    EXPECT_TRUE(token.expired());
    io.run();  // the aborted wait completes without touching the destroyed object
    EXPECT_EQ(calls, 1);
}

TEST(Reconnector, TokenLivesForOneSession) {
    boost::asio::io_context io;
    Reconnector r(1ms, 8ms);
    EXPECT_TRUE(r.token().expired());  // before start: handlers must not run
    r.start(io, [] {});
    const auto first = r.token();
    EXPECT_FALSE(first.expired());
    r.stop();
    EXPECT_TRUE(first.expired());
    r.start(io, [] {});
    EXPECT_TRUE(first.expired());  // a handler of the old session stays dead after a reopen
    EXPECT_FALSE(r.token().expired());
}

}  // namespace
