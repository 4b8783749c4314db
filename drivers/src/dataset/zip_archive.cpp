// libzip wrapper: list and read entries of a zip archive.
#include "dataset/zip_archive.h"

#include <zip.h>

#include "ldsm/error.h"

namespace ldsm::drivers::detail {

ZipArchive::ZipArchive(const std::string& path) : path_(path) {
  int error_code = 0;
  archive_ = zip_open(path.c_str(), ZIP_RDONLY, &error_code);
  if (archive_ == nullptr) {
    zip_error_t error;
    zip_error_init_with_code(&error, error_code);
    const std::string message = zip_error_strerror(&error);
    zip_error_fini(&error);
    throw InputError(path + ": cannot open zip archive: " + message);
  }
}

ZipArchive::~ZipArchive() {
  if (archive_ != nullptr) zip_discard(archive_);
}

std::vector<std::string> ZipArchive::fileNames() const {
  std::vector<std::string> names;
  const zip_int64_t n = zip_get_num_entries(archive_, 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(archive_, static_cast<zip_uint64_t>(i), 0);
    if (name == nullptr) continue;
    std::string s(name);
    if (!s.empty() && s.back() != '/') names.push_back(std::move(s));
  }
  return names;
}

std::uint64_t ZipArchive::indexOf(const std::string& name) const {
  const zip_int64_t index = zip_name_locate(archive_, name.c_str(), 0);
  if (index < 0) throw InputError(path_ + ": no entry '" + name + "' in the archive");
  return static_cast<std::uint64_t>(index);
}

void ZipArchive::read(std::uint64_t index, std::vector<unsigned char>& bytes) const {
  zip_stat_t st;
  zip_stat_init(&st);
  const char* name = zip_get_name(archive_, index, 0);
  const std::string where = path_ + ":" + (name != nullptr ? name : std::to_string(index));
  if (zip_stat_index(archive_, index, 0, &st) != 0 || (st.valid & ZIP_STAT_SIZE) == 0) {
    throw InputError(where + ": cannot read entry: " + zip_strerror(archive_));
  }
  bytes.resize(static_cast<std::size_t>(st.size));
  zip_file_t* file = zip_fopen_index(archive_, index, 0);
  if (file == nullptr) throw InputError(where + ": cannot read entry: " + zip_strerror(archive_));
  zip_uint64_t done = 0;
  while (done < st.size) {
    const zip_int64_t got = zip_fread(file, bytes.data() + done, st.size - done);
    if (got <= 0) {
      const std::string message = got < 0 ? zip_file_strerror(file) : "unexpected end of data";
      zip_fclose(file);
      throw InputError(where + ": cannot read entry: " + message);
    }
    done += static_cast<zip_uint64_t>(got);
  }
  zip_fclose(file);
}

}  // namespace ldsm::drivers::detail
