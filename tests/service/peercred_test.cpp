// SO_PEERCRED on the control socket: an unprivileged peer may read (status) but not mutate
// (shutdown); the daemon keeps running and root can still stop it.
#include <grp.h>
#include <sys/stat.h>

#include "service_fixture.hpp"

namespace fovea::service_test {
namespace {

constexpr uid_t kNobody = 65534;
constexpr gid_t kNogroup = 65534;

// In a forked child: drop to nobody/nogroup and send two requests; the replies (or the error)
// go back through `fd`, one line each.
[[noreturn]] void child_as_nobody(int fd, const std::string& socket) {
    std::string out;
    if (setgroups(0, nullptr) != 0 || setgid(kNogroup) != 0 || setuid(kNobody) != 0) {
        out = "ERR cannot drop privileges\n";
    } else {
        out = "UID " + std::to_string(getuid()) + "\n";
        for (const char* cmd : {"status", "shutdown"}) {
            auto r = daemon::control_request(socket, {{"cmd", cmd}}, 2000);
            out += r ? r->dump() + "\n" : "ERR " + r.error().message + "\n";
        }
    }
    [[maybe_unused]] auto n = ::write(fd, out.data(), out.size());
    _exit(0);
}

TEST_F(ServiceTest, NonAdminPeerGetsStatusButShutdownIsRefused) {
    if (geteuid() != 0) GTEST_SKIP() << "needs root to fork a child that setuid()s to 65534";
    auto d = start_daemon();
    ASSERT_GT(d->pid, 0);
    // Deployed, the socket's group is `fovea` and readers are its members; here nobody reaches
    // it through nogroup. The socket's 0660 mode keeps everyone else out (checked below).
    struct stat st {};
    ASSERT_EQ(::stat(socket_path().c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0660u);
    ASSERT_EQ(::chown(socket_path().c_str(), static_cast<uid_t>(-1), kNogroup), 0);

    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        ::close(fds[0]);
        child_as_nobody(fds[1], socket_path());
    }
    ::close(fds[1]);
    std::string text;
    char buf[4096];
    for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
        text.append(buf, static_cast<size_t>(n));
    ::close(fds[0]);
    int status = 0;
    waitpid(child, &status, 0);

    std::istringstream lines(text);
    std::string uid_line, status_line, shutdown_line;
    std::getline(lines, uid_line);
    std::getline(lines, status_line);
    std::getline(lines, shutdown_line);
    ASSERT_EQ(uid_line, "UID 65534") << text;
    ASSERT_EQ(status_line.rfind("ERR", 0), std::string::npos) << text;
    ASSERT_EQ(shutdown_line.rfind("ERR", 0), std::string::npos) << text;
    const json st_reply = json::parse(status_line);
    EXPECT_TRUE(st_reply.value("ok", false)) << status_line;
    EXPECT_EQ(st_reply.value("instance", ""), instance);
    const json sd_reply = json::parse(shutdown_line);
    EXPECT_FALSE(sd_reply.value("ok", true)) << shutdown_line;
    EXPECT_NE(sd_reply.value("error", "").find("permission denied"), std::string::npos)
        << shutdown_line;

    // The daemon is unaffected and counted the refusal; root may stop it.
    auto after = query("status");
    ASSERT_TRUE(after.ok());
    EXPECT_GE((*after)["control"]["rejected"].get<uint64_t>(), 1u);
    auto stop = query("shutdown");
    ASSERT_TRUE(stop.ok());
    EXPECT_TRUE((*stop).value("ok", false));
    EXPECT_EQ(d->wait(5s), 0) << d->err();
}

TEST_F(ServiceTest, PeerOutsideTheSocketGroupCannotConnect) {
    if (geteuid() != 0) GTEST_SKIP() << "needs root to fork a child that setuid()s to 65534";
    auto d = start_daemon();
    ASSERT_GT(d->pid, 0);  // socket stays root:root 0660: nobody is neither owner nor in group
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        if (setgroups(0, nullptr) != 0 || setgid(kNogroup) != 0 || setuid(kNobody) != 0) _exit(3);
        auto r = daemon::control_request(socket_path(), {{"cmd", "status"}}, 2000);
        _exit(r.ok() ? 1 : (r.error().code == EACCES ? 0 : 2));
    }
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "1: connected anyway, 2: failed but not with EACCES";
    EXPECT_TRUE(query("status").ok());
}

}  // namespace
}  // namespace fovea::service_test
