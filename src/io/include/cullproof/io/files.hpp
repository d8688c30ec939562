// Writing files so that no reader, crash or kill ever sees a partial one.
#pragma once

#include <filesystem>
#include <string_view>

namespace cullproof {

/// Writes `text` to `file` atomically: into a temporary file in the same directory (created with
/// its missing parents), flushed to disk, then renamed over the target and the directory flushed,
/// so a reader, a crash or a kill never sees a partial file: the target is the old file or the
/// whole new one. A write that fails (a full disk, a read-only or missing directory) throws
/// std::runtime_error "<file>: cannot write: <reason>" and leaves the target as it was and no
/// temporary file. A process killed while writing can leave only its temporary file, named
/// ".<name>.tmp-<pid>-<n>": hidden, and not ending in ".json", so no reader takes it for a case.
/// With `overwrite == false` an existing target is left untouched and std::runtime_error is
/// thrown ("<file>: exists already"), also when another writer creates it meanwhile (link(), not
/// rename()). An existing target that is not a regular file (a device or a pipe, as /dev/stdout)
/// is written in place, since renaming over it would replace it.
void write_file_atomic(const std::filesystem::path& file, std::string_view text, bool overwrite = true);

}  // namespace cullproof
