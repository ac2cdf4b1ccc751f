// Tests of src/ui/preset_store.cpp: round trips, listing order, refused names, the read-only default, malformed files.
#include "ui/preset_store.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "test_support.h"

namespace dentsim::ui {
namespace {

namespace fs = std::filesystem;

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A set that differs from the default in a tactile, a visual and a bur field.
Preset tunedParams() {
  Preset p = defaultPreset();
  p.sim.tissue(Material::Enamel).hardness = 0.37;
  p.looks.look(Material::Enamel).alpha = 0.5;
  p.sim.burs["round_bur_010"].cutting_ability = 0.55;
  p.looks.view.normals = NormalMode::Box64;
  return p;
}

// Sets an environment variable for one scope and puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(PresetStore, SaveThenLoadGivesAnEqualSetAndCreatesTheFolder) {
  test::TempDir dir;
  // Two levels that do not exist yet: the first save makes both.
  PresetStore store((dir.path() / "config" / "presets").string());
  const Preset tuned = tunedParams();
  Status saved = store.save("soft", tuned);
  ASSERT_TRUE(saved.ok()) << saved.message();
  EXPECT_TRUE(fs::is_regular_file(dir.path() / "config" / "presets" / "soft.json"));
  EXPECT_EQ(store.pathOf("soft"), (dir.path() / "config" / "presets" / "soft.json").string());

  Result<Preset> loaded = store.load("soft");
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  EXPECT_TRUE(*loaded == tuned);
  EXPECT_FALSE(*loaded == defaultPreset());

  // Saving again overwrites a user preset.
  Preset harder = tuned;
  harder.sim.tissue(Material::Enamel).hardness = 0.9;
  ASSERT_TRUE(store.save("soft", harder).ok());
  EXPECT_TRUE(*store.load("soft") == harder);
}

TEST(PresetStore, ListsDefaultFirstThenValidNamesInByteOrder) {
  test::TempDir dir;
  PresetStore store(dir.path().string());
  EXPECT_EQ(store.list(), std::vector<std::string>{"default"});
  for (const char* name : {"b", "a", "Z", "a.2"}) ASSERT_TRUE(store.save(name, defaultPreset()).ok()) << name;
  // Not presets: another extension, a hidden file, a folder, and a default.json that must not shadow
  // the built-in one.
  writeText(dir.path() / "notes.txt", "x");
  writeText(dir.path() / ".hidden.json", "{}");
  writeText(dir.path() / "default.json", "{}");
  fs::create_directory(dir.path() / "folder.json");
  // Byte order: 'Z' (0x5a) sorts before 'a' (0x61), and "a" before its extension "a.2".
  EXPECT_EQ(store.list(), (std::vector<std::string>{"default", "Z", "a", "a.2", "b"}));

  // A folder that does not exist lists the default alone.
  EXPECT_EQ(PresetStore((dir.path() / "missing").string()).list(), std::vector<std::string>{"default"});
}

TEST(PresetStore, RefusesBadNamesWithOneLineNamingThem) {
  test::TempDir dir;
  PresetStore store(dir.path().string());
  const std::string too_long(65, 'x');
  for (const std::string& bad : {std::string(""), std::string(".hidden"), std::string("a/b"), std::string("x y"),
                                 std::string("caf\xc3\xa9"), std::string("..")}) {
    Status s = store.save(bad, defaultPreset());
    ASSERT_FALSE(s.ok()) << "'" << bad << "'";
    EXPECT_NE(s.message().find("preset name '" + bad + "' is not valid"), std::string::npos) << s.message();
    EXPECT_EQ(s.message().find('\n'), std::string::npos);
    EXPECT_FALSE(store.load(bad).ok());
  }
  EXPECT_FALSE(store.save(too_long, defaultPreset()).ok());
  EXPECT_TRUE(store.save(std::string(64, 'x'), defaultPreset()).ok());
  // Only the 64-character preset was written.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(PresetStore, DefaultIsBuiltInAndReadOnly) {
  test::TempDir dir;
  PresetStore store(dir.path().string());
  Status s = store.save("default", tunedParams());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), "preset 'default' is built in and read-only: save under another name");
  EXPECT_FALSE(fs::exists(dir.path() / "default.json"));

  // A default.json in the folder is ignored: "default" is always the built-in set.
  writeText(dir.path() / "default.json", "not json");
  Result<Preset> d = store.load("default");
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_TRUE(*d == defaultPreset());
}

TEST(PresetStore, MalformedAndMissingFilesGiveErrorsNamingTheFile) {
  test::TempDir dir;
  PresetStore store(dir.path().string());
  const std::string path = (dir.path() / "broken.json").string();

  // Out of range: parsePreset's own message, prefixed with the path.
  writeText(path, R"({"format": "dentsim-params", "version": 1, "tissues": {"enamel": {"hardness": 1.5}}})");
  Result<Preset> r = store.load("broken");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), path + ": tissues.enamel.hardness: 1.5 is not in [0, 1]");

  // Not JSON at all.
  writeText(path, "{ \"format\": ");
  r = store.load("broken");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(path + ": ", 0), 0u) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos);

  // No such preset.
  r = store.load("absent");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find((dir.path() / "absent.json").string()), std::string::npos) << r.message();
}

TEST(PresetStore, RefusesASetThatWouldNotLoadAndWritesNothing) {
  test::TempDir dir;
  PresetStore store(dir.path().string());
  Preset bad = defaultPreset();
  bad.sim.tissue(Material::Enamel).hardness = 2.0;
  Status s = store.save("bad", bad);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("hardness"), std::string::npos) << s.message();
  EXPECT_FALSE(fs::exists(dir.path() / "bad.json"));
}

TEST(PresetStore, WithoutAFolderOnlyTheDefaultExists) {
  PresetStore store("");
  EXPECT_EQ(store.list(), std::vector<std::string>{"default"});
  EXPECT_TRUE(store.load("default").ok());
  Status s = store.save("mine", defaultPreset());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), "preset 'mine': no preset folder (set HOME or XDG_CONFIG_HOME)");
}

TEST(PresetStore, DefaultDirectoryFollowsXdgThenHome) {
  ScopedEnv home("HOME", "/home/student");
  {
    ScopedEnv xdg("XDG_CONFIG_HOME", "/cfg");
    EXPECT_EQ(defaultPresetDirectory(), "/cfg/dentsim/presets");
  }
  {
    // XDG: a relative XDG_CONFIG_HOME is invalid and ignored.
    ScopedEnv xdg("XDG_CONFIG_HOME", "relative");
    EXPECT_EQ(defaultPresetDirectory(), "/home/student/.config/dentsim/presets");
  }
  {
    ScopedEnv xdg("XDG_CONFIG_HOME", nullptr);
    EXPECT_EQ(defaultPresetDirectory(), "/home/student/.config/dentsim/presets");
    ScopedEnv no_home("HOME", nullptr);
    EXPECT_EQ(defaultPresetDirectory(), "");
  }
}

TEST(PresetNames, AcceptTheDocumentedAlphabet) {
  EXPECT_TRUE(isValidPresetName("soft"));
  EXPECT_TRUE(isValidPresetName("Soft_enamel-2.v1"));
  EXPECT_TRUE(isValidPresetName(std::string(64, 'a')));
  EXPECT_FALSE(isValidPresetName(std::string(65, 'a')));
  EXPECT_FALSE(isValidPresetName(""));
  EXPECT_FALSE(isValidPresetName(".soft"));
  EXPECT_FALSE(isValidPresetName("soft enamel"));
  EXPECT_FALSE(isValidPresetName("soft/enamel"));
}

}  // namespace
}  // namespace dentsim::ui
