#pragma once
// Output files that replace others (checkpoints, final.ckpt, .pvd series, VTK frames, timings.csv, the kept rows
// of a resumed CSV): written whole to a temporary file of their own in the same directory, flushed, then renamed
// over the old file. A reader, a crash or a kill -9 sees the old file or the new one, never a part of either, and
// two processes writing the same name never share a temporary file.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace riffle {

enum class Durability {
  kFlush,  ///< written and closed before the rename (enough for files a later write can redo: frames, tables)
  kSync,   ///< also the file fsync'd before the rename and its directory after it (checkpoints: they must survive
           ///< a power cut, or the next resume has nothing to resume from)
};

/// A name for a temporary file beside `path` that no other process or call uses: "<name>.<pid>.<counter>.tmp".
std::filesystem::path unique_temporary_path(const std::filesystem::path& path);

/// Replaces (or creates) `path` with `bytes` by way of a unique temporary file and a rename. On failure the old
/// file is untouched, the temporary file is removed, and std::runtime_error names the path and the reason.
void replace_file(const std::filesystem::path& path, std::string_view bytes, Durability durability);

/// True for a name unique_temporary_path() makes: "<name>.<digits>.<digits>.tmp".
bool is_temporary_name(const std::string& file_name);

/// Removes the temporary files a killed process left in `directory` (not in its sub-directories); files of other
/// names are kept. Only for a folder whose writer holds its lock (engine/output/output_lock.hpp): nobody else can be
/// writing them. Returns how many were removed; errors are ignored (a leftover costs disk space, nothing else).
std::size_t remove_stale_temporaries(const std::filesystem::path& directory);

}  // namespace riffle
