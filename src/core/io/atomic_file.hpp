#pragma once
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace sdfgen {

// Writes a file so that readers only ever see the old content or the complete new one.
//
// `write` fills a stream that goes to a temporary file beside the target; only when it has
// returned, the stream is flushed without error and the data is fsynced is the temporary renamed
// over the target. On any failure (an exception from `write`, a full disk, ...) the temporary is
// removed, the old file is left as it was and Error("PATH: problem") is thrown. Also:
// - a symbolic link (or a chain of them) is written through: its final target is replaced and the
//   link stays a link;
// - an existing file keeps its permission bits (and owner, where allowed); a new one gets
//   0666 minus the umask, like any file the user creates;
// - a target that exists but is not a regular file (/dev/stdout, a FIFO, a terminal) is written
//   directly, since it cannot be replaced: nothing to keep, and no atomicity either;
// - SIGINT, SIGTERM, SIGHUP and SIGXFSZ (the file-size limit; when their action is the default)
//   remove the temporary files still being written, then terminate the process as the signal
//   would have;
// - the temporary is named after the target (NAME.tmp-...), its name shortened where needed so
//   that a target name of any valid length (up to 255 bytes) can be written;
// - two processes writing one path at once both succeed, and the file is the complete output of
//   whichever renamed last (never a mixture);
// - a file with several hard links gets a new inode: the other names keep the old content.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// The same for libraries that can only write to a path (libzip, OpenVDB's io::File): `writeTo`
// gets the temporary's path and must write the whole file there (it may replace that file); the
// rest is as above. A target that is not a regular file is passed to `writeTo` itself.
void writeFileAtomicallyAt(const std::string& path, const std::function<void(const std::string& temporaryPath)>& writeTo);

// Throws Error("OUTPUT: is the input file INPUT; refusing to overwrite it") when `output` names
// one of `inputs` (empty ones are skipped): the same file by device and inode (so also through
// symbolic links and hard links), or, where either does not exist yet, the same canonical path.
// Every command calls it before it starts work.
void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs);

} // namespace sdfgen
