// File helpers: whole-or-nothing writes and size-bounded reads of regular files with clear
// errors, the check that no output is an input, checksums, and escaping text for the HTML and
// XML files brdffit writes.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace brdffit {

// Largest file read_file reads unless told otherwise: well above any table brdffit knows (a
// MERL 90x90x360 table is 70 MB), so that a device or a runaway file is refused before it is
// read rather than after memory ran out.
constexpr uint64_t kMaxInputBytes = uint64_t{4} << 30;

// Writes to a temporary file created exclusively (mkstemp) in `path`'s folder, flushes it and
// renames it over `path`, so readers see the old file or the complete new one, never a partial
// one. What `path` finally names (links followed) decides: a regular file or nothing is
// replaced (a symbolic link to a regular file is replaced by the file, its target left alone); a
// FIFO, socket, terminal or /dev/null (`/dev/stdout` through its links) is written through; a
// folder or another device is refused. Throws Error on failure.
void write_file_atomic(const std::string& path, const std::string& contents);

// The same for writers that need a file name (e.g. an image library choosing the format by the
// extension): `write` fills the temporary file `temp_path`, created exclusively beside `path`
// and ending like it in `extension` (e.g. ".png"), and returns an error message, empty on
// success; then it is renamed over `path`. Throws Error naming `path` on failure.
void replace_file_atomic(const std::string& path, const std::string& extension,
                         const std::function<std::string(const std::string& temp_path)>& write);

// Reads a whole regular file into memory; throws Error naming the file when it cannot, when it
// is not a regular file (a FIFO is refused without blocking) or when it is larger than max_bytes.
std::string read_file(const std::string& path, uint64_t max_bytes = kMaxInputBytes);

// Throws Error naming `path` unless it is a regular file (following links) no larger than max_bytes;
// returns its size. For readers that stream a file instead of reading it whole.
uint64_t check_input_file(const std::string& path, uint64_t max_bytes = kMaxInputBytes);

// Where the folders of a command's outputs come from: there already (a file written with
// write_file_atomic, which makes no folder), or made by the command (sphere's --images-out/MODEL/).
enum class OutputFolders { Exist, Made };

// Commands call this before they start work: throws Error when an output is the same file as an
// input or as another output (by device and inode, so other spellings of a path and hard links
// count), is an existing file that is not a regular file, or cannot be made now: its folder does
// not exist (with OutputFolders::Made: the nearest existing one above it) or is no folder this
// process may write into; the message names the path and the reason. Empty paths are ignored (an
// output not asked for); outputs that do not exist yet only need distinct spellings, compared
// after making them absolute and normal. Inputs that are folders are compared like files.
void check_outputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs,
                   OutputFolders folders = OutputFolders::Exist);

// The same for a folder a command writes its outputs into, making it (and its parents) when
// missing (batch's --out): throws Error unless it is a folder, or nothing below a folder this
// process may write into.
void check_output_folder(const std::string& folder);

// `path` made absolute against the working folder and lexically normal (no . or ..), for
// documents that name their inputs and are read from another folder.
std::string absolute_path(const std::string& path);

// SHA-256 of a file's bytes as lowercase hex.
std::string sha256_file(const std::string& path);

// The length (1 to 4) of the well-formed UTF-8 sequence at text[i], or 0 when there is none:
// a stray continuation byte, a missing one, an overlong form, a surrogate or above U+10FFFF.
size_t utf8_sequence_length(const std::string& text, size_t i);

// Whether all of `text` is well-formed UTF-8. File names are bytes and need not be.
bool valid_utf8(const std::string& text);

// Text escaped to stand in HTML or XML content and attribute values (& < > " ').
std::string escape_markup(const std::string& text);

// Text escaped to stand in a Markdown table cell as plain text: HTML markup as by escape_markup
// (Markdown passes raw HTML through), Markdown's own punctuation (\ ` * _ [ ] |) backslashed,
// and line breaks and other control characters turned into spaces so a row stays one line.
std::string escape_markdown(const std::string& text);

// "1 material", "3 materials": a count and its noun, plural unless the count is one.
std::string count_of(size_t count, const std::string& noun);

// "a", "a or b", "a, b or c": words for a sentence, the last two joined by `conjunction` ("or",
// "and"); empty for none.
std::string join_words(const std::vector<std::string>& words, const std::string& conjunction);

// A CSV field: quoted, with quotes doubled, when it holds a comma, quote or line break. Every
// CSV file brdffit writes goes through it.
std::string csv_field(const std::string& text);

// write_file_atomic's temporary file for folder/name is folder/ + this + name + "." + a unique
// six-character suffix (+ the extension); a killed process leaves them behind (see
// remove_stale_temp_files). The prefix tells them from the user's files.
inline const std::string kTempPrefix = ".brdffit-tmp.";

// Removes the temporary files write_file_atomic leaves in `folder` when its process was killed
// (names starting with kTempPrefix and ending in a mkstemp suffix), and nothing else. Call it
// only while holding the folder (OutputFolderLock), so no live writer's file is removed.
// Returns how many it removed.
int remove_stale_temp_files(const std::string& folder);

}  // namespace brdffit
