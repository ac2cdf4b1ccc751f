// fileHash: XXH3 streamed over 1 MiB reads.
#include "io/file_hash.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include <xxhash.h>

#include "io/atomic_file.h"

namespace dentsim {

Result<uint64_t> fileHash(const std::string& path) {
  // fopen of a FIFO would wait for a writer.
  if (Status regular = requireRegularFile(path); !regular) return regular.error();
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) return makeError(path, std::strerror(errno));
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(), &XXH3_freeState);
  XXH3_64bits_reset(state.get());
  std::vector<unsigned char> buffer(size_t{1} << 20);
  for (;;) {
    const size_t got = std::fread(buffer.data(), 1, buffer.size(), file.get());
    XXH3_64bits_update(state.get(), buffer.data(), got);
    if (got < buffer.size()) break;
  }
  if (std::ferror(file.get())) return makeError(path, "read error");
  return XXH3_64bits_digest(state.get());
}

uint64_t bytesHash(const void* data, size_t size) { return XXH3_64bits(data, size); }

}  // namespace dentsim
