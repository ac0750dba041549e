#include "io/output_file.h"

#include <fcntl.h>
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
        // A new file beside the target, with the target's permissions (a new
        // target: 0666 less the umask, as any created file).
        for (int attempt = 0; attempt < kTemporaryNameAttempts && !file; ++attempt) {
            const QByteArray temporary =
                target + ".vssim-" + QByteArray::number(::getpid()) + "-" + QByteArray::number(attempt);
            const int fd = ::open(temporary.constData(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            if (fd < 0 && errno == EEXIST) continue;
            if (fd < 0) return fail(errno, QStringLiteral("cannot create a temporary file beside it: "));
            file.reset(new OutputFile(fd, true, path));
            file->temporary_ = temporary;
            if (exists) {
                // Keep the owner where we may (root writing a user's file) and the mode.
                // (Not permitted for others: then the new file is ours, as with any rewrite by rename.)
                if (::fchown(fd, st.st_uid, st.st_gid) != 0 && errno != EPERM) return fail(errno);
                if (::fchmod(fd, st.st_mode & 07777) != 0) return fail(errno);
            }
        }
        if (!file) return fail(EEXIST, QStringLiteral("cannot create a temporary file beside it: "));
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
    if (!temporary_.isEmpty() && ::fsync(fd_) != 0) return failWith(errno);
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) return failWith(errno);
    if (temporary_.isEmpty()) return true;
    if (::rename(temporary_.constData(), target_.constData()) != 0) return failWith(errno);
    temporary_.clear();
    return true;
}

}  // namespace vssim
