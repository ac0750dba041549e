// Where a command's output goes (vssim run's CSV): standard output or a named
// file, with every failure reported with the system's reason.
//
// A named file is written so that nothing but its content changes:
// - a regular file with a single link (or a new file) is written to a
//   temporary file beside it and renamed over it by commit(), so a run that
//   fails leaves the old file as it was. The temporary file has no name
//   while it is written (Linux's O_TMPFILE, in the target's folder), so a
//   process killed outright (SIGKILL) leaves nothing behind; commit() links
//   it in as TARGET.vssim-PID-N and renames that over the target. Where the
//   file system or a missing /proc rule that out, the temporary file is named
//   TARGET.vssim-PID-N from the start. Either way, open() first removes the
//   TARGET.vssim-PID-N files of processes that no longer exist (killed
//   before their rename); a living process's are never touched;
// - anything else is written in place, since renaming over it would replace
//   it: a device (a null device would become a plain file), a FIFO, a regular
//   file with other hard links (each link must see the new content);
// - a symbolic link is followed: its final target gets the content, the link
//   stays a link;
// - a directory is refused.
// POSIX calls rather than QSaveFile, which renames over devices too and loses
// the reason of a failed write ("Unknown error").
#pragma once

#include <QByteArray>
#include <QString>
#include <memory>

namespace vssim {

class OutputFile {
public:
    // Descriptor 1, not closed by this object. A closed standard output
    // fails at the first write ("Bad file descriptor").
    static std::unique_ptr<OutputFile> standardOutput();
    // Opens `path` as described above; nullptr and *error (the path and the
    // reason) when it cannot. A FIFO's open waits for a reader.
    static std::unique_ptr<OutputFile> open(const QString& path, QString* error);
    // A command's --out: open(path), or standard output when `path` is empty.
    static std::unique_ptr<OutputFile> openOrStandardOutput(const QString& path, QString* error);
    // Removes the temporary file when commit() did not succeed.
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    // Writes all of `data`; false (and error() set) on the first failure,
    // and every later call fails too.
    bool write(const QByteArray& data);
    // All is written: flushes to the disk and renames a temporary file into
    // place, or closes the file. False (and error() set) on failure.
    bool commit();

    // The path as given, or "standard output", for messages.
    const QString& name() const { return name_; }
    // The system's reason for the first failure ("No space left on device").
    const QString& error() const { return error_; }
    // Whether the content goes straight to the target (see above).
    bool inPlace() const { return !unnamed_ && temporary_.isEmpty(); }

private:
    OutputFile(int fd, bool owned, QString name) : fd_(fd), owned_(owned), name_(std::move(name)) {}
    bool failWith(int errorNumber);

    int fd_;
    bool owned_;            // close fd_ when done
    QString name_;          // as given
    QByteArray target_;     // the final path, symbolic links followed (named files only)
    bool unnamed_ = false;  // fd_ is a file with no name yet (O_TMPFILE), linked in by commit()
    QByteArray temporary_;  // the named file renamed over target_ by commit(); empty when in place or unnamed
    QString error_;
};

}  // namespace vssim
