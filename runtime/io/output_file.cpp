#include "io/output_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <climits>
#include <cstring>

#include <QFile>

namespace vssim {

namespace {

constexpr int kMaxLinkHops = 40;  // as the kernel's own limit (ELOOP beyond)
constexpr int kTemporaryNameAttempts = 100;

QString reason(int errorNumber) { return QString::fromLocal8Bit(std::strerror(errorNumber)); }

// Follows symbolic links from `path` to the name they finally lead to, which
// may not exist yet (a dangling link: the file is created where it points).
// False and *errorNumber set for a loop or an unreadable link.
bool followLinks(QByteArray path, QByteArray* out, int* errorNumber) {
    for (int hop = 0; hop < kMaxLinkHops; ++hop) {
        struct stat st;
        if (::lstat(path.constData(), &st) != 0 || !S_ISLNK(st.st_mode)) {
            *out = path;  // not a link (or nothing there): the open says what is wrong
            return true;
        }
        char buffer[PATH_MAX];
        const ssize_t n = ::readlink(path.constData(), buffer, sizeof buffer);
        if (n < 0 || n == static_cast<ssize_t>(sizeof buffer)) {
            *errorNumber = n < 0 ? errno : ENAMETOOLONG;
            return false;
        }
        QByteArray target(buffer, static_cast<int>(n));
        if (!target.startsWith('/')) target.prepend(path.left(path.lastIndexOf('/') + 1));  // relative to the link
        path = target;
    }
    *errorNumber = ELOOP;
    return false;
}

// The name a temporary file of `target` has (made by process `pid`, its
// attempt-th try): TARGET.vssim-PID-N, in the target's folder.
QByteArray temporaryName(const QByteArray& target, pid_t pid, int attempt) {
    return target + ".vssim-" + QByteArray::number(pid) + "-" + QByteArray::number(attempt);
}

// Reads the digits of `text` from *at: false unless there is at least one
// and the number fits `limit`.
bool readNumber(const char* text, std::size_t* at, long long limit, long long* value) {
    const std::size_t start = *at;
    long long n = 0;
    for (; text[*at] >= '0' && text[*at] <= '9'; ++*at) {
        n = 10 * n + (text[*at] - '0');
        if (n > limit) return false;
    }
    *value = n;
    return *at > start;
}

// Removes the temporary files of `target` (TARGET.vssim-PID-N, regular
// files) whose process no longer exists: a run killed before it renamed its
// temporary file over the target. A process that exists, or whose existence
// cannot be told (kill(pid, 0) other than "no such process"), keeps its
// own, which it may be about to rename. Failures are ignored: the run goes
// on whatever is left.
void removeStaleTemporaries(const QByteArray& target) {
    const qsizetype slash = target.lastIndexOf('/');
    const QByteArray folder = slash < 0 ? QByteArray(".") : target.left(slash + 1);
    const QByteArray prefix = target.mid(slash + 1) + ".vssim-";
    DIR* dir = ::opendir(folder.constData());
    if (!dir) return;
    const int dirFd = ::dirfd(dir);
    while (const dirent* entry = ::readdir(dir)) {
        const char* name = entry->d_name;
        if (std::strncmp(name, prefix.constData(), static_cast<std::size_t>(prefix.size())) != 0) continue;
        std::size_t at = static_cast<std::size_t>(prefix.size());
        long long pid = 0, attempt = 0;
        if (!readNumber(name, &at, INT_MAX, &pid) || pid < 1 || name[at++] != '-' ||
            !readNumber(name, &at, INT_MAX, &attempt) || name[at] != '\0')
            continue;
        if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        struct stat st;
        if (::fstatat(dirFd, name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode))
            ::unlinkat(dirFd, name, 0);
    }
    ::closedir(dir);
}

// A file with no name in the folder of `target` (O_TMPFILE), writable, or -1
// when the system cannot make one or could not give it a name later: commit()
// names it through /proc/self/fd, which must lead to it.
int openUnnamed(const QByteArray& target) {
#ifdef O_TMPFILE
    const qsizetype slash = target.lastIndexOf('/');
    const QByteArray folder = slash < 0 ? QByteArray(".") : slash == 0 ? QByteArray("/") : target.left(slash);
    const int fd = ::open(folder.constData(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (fd < 0) return -1;
    struct stat byFd, byProc;
    if (::fstat(fd, &byFd) == 0 && ::stat(("/proc/self/fd/" + QByteArray::number(fd)).constData(), &byProc) == 0 &&
        byFd.st_dev == byProc.st_dev && byFd.st_ino == byProc.st_ino)
        return fd;
    ::close(fd);
#else
    (void)target;
#endif
    return -1;
}

}  // namespace

std::unique_ptr<OutputFile> OutputFile::standardOutput() {
    return std::unique_ptr<OutputFile>(new OutputFile(STDOUT_FILENO, false, QStringLiteral("standard output")));
}

std::unique_ptr<OutputFile> OutputFile::openOrStandardOutput(const QString& path, QString* error) {
    return path.isEmpty() ? standardOutput() : open(path, error);
}

std::unique_ptr<OutputFile> OutputFile::open(const QString& path, QString* error) {
    auto fail = [&](int errorNumber, const QString& what = {}) {
        *error = QStringLiteral("%1: %2%3").arg(path, what, reason(errorNumber));
        return nullptr;
    };
    // What the path leads to, as the kernel follows it (also /dev/stdout and
    // /proc/self/fd/N, whose link text is no path): anything but a regular
    // file with one link is written in place, through the path as given.
    const QByteArray given = QFile::encodeName(path);
    struct stat leads;
    if (::stat(given.constData(), &leads) == 0 && !S_ISDIR(leads.st_mode) &&
        !(S_ISREG(leads.st_mode) && leads.st_nlink == 1)) {
        if (::access(given.constData(), W_OK) != 0) return fail(errno);
        const int fd = ::open(given.constData(), O_WRONLY | O_TRUNC | O_CLOEXEC | O_NOCTTY);
        if (fd < 0) return fail(errno);
        std::unique_ptr<OutputFile> file(new OutputFile(fd, true, path));
        file->target_ = given;
        return file;
    }
    QByteArray target;
    int errorNumber = 0;
    if (!followLinks(given, &target, &errorNumber)) return fail(errorNumber);
    struct stat st;
    const bool exists = ::stat(target.constData(), &st) == 0;
    if (!exists && errno != ENOENT) return fail(errno);
    if (exists && S_ISDIR(st.st_mode)) return fail(EISDIR);
    // A file we may not write is not ours to replace either (as QSaveFile, and the shell's `>`).
    if (exists && ::access(target.constData(), W_OK) != 0) return fail(errno);
    std::unique_ptr<OutputFile> file;
    if (exists && !(S_ISREG(st.st_mode) && st.st_nlink == 1)) {
        // In place. O_TRUNC empties a regular file and means nothing to a
        // device or a FIFO; no O_CREAT: what is there is what gets written.
        const int fd = ::open(target.constData(), O_WRONLY | O_TRUNC | O_CLOEXEC | O_NOCTTY);
        if (fd < 0) return fail(errno);
        file.reset(new OutputFile(fd, true, path));
    } else {
        removeStaleTemporaries(target);
        // A new file beside the target, with no name if it may be (see
        // output_file.h), else named, and with the target's permissions (a
        // new target: 0666 less the umask, as any created file).
        if (const int fd = openUnnamed(target); fd >= 0) {
            file.reset(new OutputFile(fd, true, path));
            file->unnamed_ = true;
        }
        for (int attempt = 0; attempt < kTemporaryNameAttempts && !file; ++attempt) {
            const QByteArray temporary = temporaryName(target, ::getpid(), attempt);
            const int fd = ::open(temporary.constData(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            if (fd < 0 && errno == EEXIST) continue;
            if (fd < 0) return fail(errno, QStringLiteral("cannot create a temporary file beside it: "));
            file.reset(new OutputFile(fd, true, path));
            file->temporary_ = temporary;
        }
        if (!file) return fail(EEXIST, QStringLiteral("cannot create a temporary file beside it: "));
        if (exists) {
            // Keep the owner where we may (root writing a user's file) and the mode.
            // (Not permitted for others: then the new file is ours, as with any rewrite by rename.)
            if (::fchown(file->fd_, st.st_uid, st.st_gid) != 0 && errno != EPERM) return fail(errno);
            if (::fchmod(file->fd_, st.st_mode & 07777) != 0) return fail(errno);
        }
    }
    file->target_ = target;
    return file;
}

OutputFile::~OutputFile() {
    if (owned_ && fd_ >= 0) ::close(fd_);
    if (!temporary_.isEmpty()) ::unlink(temporary_.constData());
}

bool OutputFile::failWith(int errorNumber) {
    if (error_.isEmpty()) {
        error_ = reason(errorNumber);
        if (errorNumber == EBADF && !owned_) error_ += QStringLiteral(" (it is closed)");
    }
    return false;
}

bool OutputFile::write(const QByteArray& data) {
    if (!error_.isEmpty()) return false;
    const char* p = data.constData();
    qsizetype left = data.size();
    while (left > 0) {
        const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(left));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return failWith(errno);
        if (n == 0) return failWith(EIO);  // no progress on a blocking descriptor: give up rather than spin
        p += n;
        left -= n;
    }
    return true;
}

bool OutputFile::commit() {
    if (!error_.isEmpty()) return false;
    if (!owned_) return true;  // standard output: written as it went
    // A file system may report a full disk only when the data reach it.
    if (!inPlace() && ::fsync(fd_) != 0) return failWith(errno);
    if (unnamed_) {
        // A name of its own first (linkat cannot replace the target), while
        // the descriptor still holds it.
        const QByteArray self = "/proc/self/fd/" + QByteArray::number(fd_);
        for (int attempt = 0; attempt < kTemporaryNameAttempts && temporary_.isEmpty(); ++attempt) {
            const QByteArray temporary = temporaryName(target_, ::getpid(), attempt);
            if (::linkat(AT_FDCWD, self.constData(), AT_FDCWD, temporary.constData(), AT_SYMLINK_FOLLOW) == 0)
                temporary_ = temporary;
            else if (errno != EEXIST)
                return failWith(errno);
        }
        if (temporary_.isEmpty()) return failWith(EEXIST);
        unnamed_ = false;
    }
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) return failWith(errno);
    if (temporary_.isEmpty()) return true;
    if (::rename(temporary_.constData(), target_.constData()) != 0) return failWith(errno);
    temporary_.clear();
    return true;
}

}  // namespace vssim
