// The sdfgen-text field format: exact round trips, line-numbered errors for every kind of bad
// file, and atomic saving that never leaves a half-written or temporary file behind.
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/sparse_field.hpp"

#include "support/checks.hpp"
#include "core/io/formats/format.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

namespace fs = std::filesystem;

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

float fromBits(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Lines of a small valid file: a 2x1x1 grid, so the values are on lines 8 and 9.
std::vector<std::string> validLines() {
    return {"sdfgen-text 1", "source in.obj", "dims 2 1 1", "origin 0 -1 2.5", "voxel 0.5", "method rays rays=64",
            "values",        "1.5",           "-0.25"};
}

std::string join(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

class FieldText : public test::ScratchFolderTest {
protected:

    // Loading `contents` must fail with "PATH:LINE: ..." mentioning `word`.
    void expectLineError(const std::string& contents, int line, const std::string& word) {
        const std::string path = write("bad.sdf", contents);
        const std::string message = errorFrom([&] { loadFieldText(path); });
        EXPECT_CONTAINS(message, path + ":" + std::to_string(line) + ": ");
        EXPECT_CONTAINS(message, word);
    }
    void expectLineError(std::vector<std::string> lines, int line, const std::string& word) {
        expectLineError(join(lines), line, word);
    }
    // validLines() with line `number` (1-based) replaced.
    static std::vector<std::string> with(int number, const std::string& text) {
        std::vector<std::string> lines = validLines();
        lines[std::size_t(number - 1)] = text;
        return lines;
    }
    static std::vector<std::string> without(int number) {
        std::vector<std::string> lines = validLines();
        lines.erase(lines.begin() + (number - 1));
        return lines;
    }

    std::vector<std::string> folderContents() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
        return names;
    }
    void expectNoTemporaryFiles() const {
        for (const std::string& name : folderContents()) EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
    }

};

Field smallField() {
    Field field;
    field.source = "in.obj";
    field.method = "rays";
    field.parameters = {{"rays", "64"}};
    field.grid.dims = {2, 1, 1};
    field.grid.origin = {0.0f, -1.0f, 2.5f};
    field.grid.voxel = 0.5f;
    field.values = {1.5f, -0.25f};
    return field;
}

void expectIdentical(const Field& a, const Field& b) {
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.parameters, b.parameters);
    EXPECT_EQ(a.grid.dims, b.grid.dims);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(a.grid.origin[k]), bits(b.grid.origin[k])) << "origin " << k;
    EXPECT_EQ(bits(a.grid.voxel), bits(b.grid.voxel));
    ASSERT_EQ(a.values.size(), b.values.size());
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        EXPECT_EQ(bits(a.values[i]), bits(b.values[i])) << "value " << i << ": " << a.values[i] << " vs " << b.values[i];
    }
    EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)), 0);
}

// ---- Round trips -------------------------------------------------------------------------------

TEST_F(FieldText, ValidFileLoads) {
    const Field field = loadFieldText(write("ok.sdf", join(validLines())));
    expectIdentical(field, smallField());
    EXPECT_EQ(field.grid.origin, glm::dvec3(0, -1, 2.5));
}

TEST_F(FieldText, CrLfLineEndingsLoad) {
    std::string text;
    for (const std::string& line : validLines()) text += line + "\r\n";
    expectIdentical(loadFieldText(write("crlf.sdf", text)), smallField());
}

TEST_F(FieldText, AwkwardValuesRoundTripBitForBit) {
    Field field;
    field.source = "meshes/my bunny (v2).obj";
    field.method = "rays";
    field.parameters = {{"rays", "64"}, {"seed", "12345"}, {"mode", "a-b_c.d"}};
    field.grid.dims = {3, 4, 5};
    field.grid.origin = {-1.2345678f, 1e-7f, 3.0f / 7.0f};
    field.grid.voxel = 0.0137f;

    const float denormMin = std::numeric_limits<float>::denorm_min();
    field.values = {0.0f,
                    -0.0f,
                    denormMin,
                    -denormMin,
                    1e-40f,                                      // denormal
                    fromBits(0x007FFFFFu),                       // largest denormal
                    std::numeric_limits<float>::min(),           // smallest normal
                    1e-38f,
                    3.4e38f,
                    std::numeric_limits<float>::max(),
                    std::numeric_limits<float>::lowest(),
                    1.0f / 3.0f,
                    -2.0f / 3.0f,
                    0.1f,
                    std::nextafter(1.0f, 0.0f),
                    std::nextafter(1.0f, 2.0f),
                    1.0f,
                    -1.0f,
                    16777216.0f,
                    16777217.0f * 1.0f,
                    123456789.0f,
                    std::numeric_limits<float>::epsilon()};
    std::mt19937 rng(20240611u);
    std::uniform_real_distribution<float> mantissa(1.0f, 10.0f);
    std::uniform_int_distribution<int> exponent(-45, 38);
    while (field.values.size() < field.grid.sampleCount()) {
        const float v = mantissa(rng) * std::pow(10.0f, float(exponent(rng))) * (rng() % 2 ? 1.0f : -1.0f);
        if (std::isfinite(v)) field.values.push_back(v);
    }
    ASSERT_EQ(field.values.size(), 60u);

    const std::string path = (dir_ / "awkward.sdf").string();
    saveFieldText(field, path);
    expectIdentical(loadFieldText(path), field);
}

TEST_F(FieldText, RandomBitPatternsRoundTripBitForBit) {
    Field field;
    field.source = "";
    field.method = "m";
    field.grid.dims = {17, 13, 11};
    field.grid.origin = {fromBits(0x80000001u), 1e-30f, -7.0f};
    field.grid.voxel = fromBits(0x30000001u); // about 4.7e-10
    std::mt19937 rng(7u);
    while (field.values.size() < field.grid.sampleCount()) {
        const float v = fromBits(std::uint32_t(rng()));
        if (std::isfinite(v)) field.values.push_back(v);
    }
    const std::string path = (dir_ / "random.sdf").string();
    saveFieldText(field, path);
    expectIdentical(loadFieldText(path), field);
}

TEST_F(FieldText, SourceWithOuterSpacesRoundTrips) {
    Field field = smallField();
    field.source = "  spaced name.obj ";
    field.parameters.clear();
    const std::string path = (dir_ / "spaced.sdf").string();
    saveFieldText(field, path);
    expectIdentical(loadFieldText(path), field);
}

// ---- Malformed files: "PATH:LINE: problem" -----------------------------------------------------

TEST_F(FieldText, MissingFileIsAnError) {
    const std::string path = (dir_ / "nothing.sdf").string();
    const std::string message = errorFrom([&] { loadFieldText(path); });
    EXPECT_CONTAINS(message, path);
    EXPECT_CONTAINS(message, "cannot open");
}

TEST_F(FieldText, EmptyFileIsAnError) {
    // The magic was expected on line 1; there is no line 0.
    expectLineError("", 1, "file ends");
}

TEST_F(FieldText, BadMagic) {
    expectLineError(with(1, "sdfgen-txt 1"), 1, "sdfgen-text");
    expectLineError(with(1, "P6"), 1, "sdfgen-text");
    expectLineError(with(1, "sdfgen-text"), 1, "sdfgen-text");
}

TEST_F(FieldText, UnsupportedVersion) {
    expectLineError(with(1, "sdfgen-text 2"), 1, "unsupported version 2");
    expectLineError(with(1, "sdfgen-text one"), 1, "version");
    expectLineError(with(1, "sdfgen-text 1 extra"), 1, "unexpected text");
}

TEST_F(FieldText, MissingSourceLine) { expectLineError(without(2), 2, "'source"); }

TEST_F(FieldText, BadDims) {
    expectLineError(without(3), 3, "'dims");
    expectLineError(with(3, "dims 2 x 1"), 3, "not a valid number");
    expectLineError(with(3, "dims 2 1.5 1"), 3, "not a valid number");
    expectLineError(with(3, "dims 0 1 1"), 3, "at least 1");
    expectLineError(with(3, "dims 2 -1 1"), 3, "at least 1");
    expectLineError(with(3, "dims 2 1"), 3, "not a valid number");
    expectLineError(with(3, "dims 2 1 1 1"), 3, "unexpected text");
    expectLineError(with(3, "dims 99999999999 1 1"), 3, "not a valid number");
    expectLineError(with(3, "dims 100000 100000 100000"), 3, "too large");
}

TEST_F(FieldText, BadOrigin) {
    expectLineError(with(4, "origin nan 0 0"), 4, "not finite");
    expectLineError(with(4, "origin 0 inf 0"), 4, "not finite");
    expectLineError(with(4, "origin 0 0 1e309"), 4, "origin");
    expectLineError(with(4, "origin 0 0"), 4, "not a valid number");
    expectLineError(with(4, "origin 0 0 zero"), 4, "not a valid number");
}

TEST_F(FieldText, VoxelMustBePositive) {
    expectLineError(with(5, "voxel 0"), 5, "positive");
    expectLineError(with(5, "voxel -0"), 5, "positive");
    expectLineError(with(5, "voxel -0.5"), 5, "positive");
    expectLineError(with(5, "voxel nan"), 5, "not finite");
    expectLineError(with(5, "voxel"), 5, "'voxel");
}

TEST_F(FieldText, MethodLine) {
    expectLineError(without(6), 6, "'method");
    expectLineError(with(6, "method"), 6, "'method");
    expectLineError(with(6, "method rays rays"), 6, "key=value");
    expectLineError(with(6, "method rays =64"), 6, "key=value");
    expectLineError(with(6, "method rays rays="), 6, "key=value");
}

TEST_F(FieldText, MethodParametersAreParsed) {
    const Field field = loadFieldText(write("params.sdf", join(with(6, "method rays  rays=64 seed=7 "))));
    EXPECT_EQ(field.method, "rays");
    const std::vector<std::pair<std::string, std::string>> expected = {{"rays", "64"}, {"seed", "7"}};
    EXPECT_EQ(field.parameters, expected);
}

TEST_F(FieldText, ValuesLineMissing) {
    expectLineError(without(7), 7, "'values'");
    expectLineError(with(7, "values 2"), 7, "'values'");
}

TEST_F(FieldText, NonNumberValue) {
    expectLineError(with(9, "abc"), 9, "not a valid number");
    expectLineError(with(8, "1,5"), 8, "not a valid number");
    expectLineError(with(8, ""), 8, "not a valid number");
    expectLineError(with(9, "+1"), 9, "not a valid number");
}

TEST_F(FieldText, NanOrInfiniteValue) {
    expectLineError(with(9, "nan"), 9, "not finite");
    expectLineError(with(8, "-inf"), 8, "not finite");
    expectLineError(with(9, "1e39"), 9, "value");
}

TEST_F(FieldText, FewerValues) {
    std::vector<std::string> lines = validLines();
    lines.pop_back();
    expectLineError(lines, 8, "file ends after 1 of 2 values");
    lines.pop_back();
    expectLineError(lines, 7, "file ends after 0 of 2 values");
}

TEST_F(FieldText, HeaderCutShort) {
    const std::string text = join(validLines());
    expectLineError(text.substr(0, text.find("origin")), 3, "file ends where 'origin' was expected");
    // Cut in the middle of the dims line.
    expectLineError(text.substr(0, text.find("dims 2 1") + 8), 3, "");
}

TEST_F(FieldText, CutInsideAValueLine) {
    std::vector<std::string> lines = with(3, "dims 3 1 1");
    lines.push_back("-12.75");
    const std::string text = join(lines); // values on lines 8, 9, 10
    // Cut after "-0." on line 9 (which alone would read as a number): the third value is missing.
    expectLineError(text.substr(0, text.find("-0.25") + 3), 9, "");
    // Cut after "-" on line 9.
    expectLineError(text.substr(0, text.find("-0.25") + 1), 9, "");
}

TEST_F(FieldText, CutInsideTheLastValueLine) {
    // The writer ends every line with '\n'; a file whose last value "-12.75" was cut to "-12.7"
    // (no final line break) is truncated, not a field with a slightly different last value.
    std::vector<std::string> lines = with(3, "dims 3 1 1");
    lines.push_back("-12.75");
    const std::string text = join(lines);
    ASSERT_NO_THROW(loadFieldText(write("whole.sdf", text)));
    expectLineError(text.substr(0, text.size() - 2), 10, "");
}

TEST_F(FieldText, TrailingGarbage) {
    std::vector<std::string> lines = validLines();
    lines.push_back("3.0");
    expectLineError(lines, 10, "unexpected content after the last of 2 values");
    lines.back() = "garbage";
    expectLineError(lines, 10, "unexpected content");
    expectLineError(join(validLines()) + "\x01\x02", 10, "unexpected content");
}

TEST_F(FieldText, ExtraTokenOnValueLine) {
    expectLineError(with(8, "1.5 2.5"), 8, "unexpected text");
    expectLineError(with(9, "-0.25x"), 9, "not a valid number");
    expectLineError(with(9, "-0.25\t"), 9, "not a valid number");
}

// ---- Atomic saving -----------------------------------------------------------------------------

TEST_F(FieldText, SaveReplacesExistingFile) {
    const std::string path = write("field.sdf", "old contents that are not a field\n");
    const Field field = smallField();
    saveFieldText(field, path);
    expectIdentical(loadFieldText(path), field);
    EXPECT_EQ(folderContents(), std::vector<std::string>{"field.sdf"});
}

TEST_F(FieldText, SavedFileIsWorldReadable) {
    const std::string path = (dir_ / "field.sdf").string();
    saveFieldText(smallField(), path);
    struct stat st {};
    ASSERT_EQ(stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0644u);
}

TEST_F(FieldText, SaveLeavesNoTemporaryFiles) {
    const std::string path = (dir_ / "field.sdf").string();
    saveFieldText(smallField(), path);
    saveFieldText(smallField(), path);
    EXPECT_EQ(folderContents(), std::vector<std::string>{"field.sdf"});
    expectNoTemporaryFiles();
}

TEST_F(FieldText, SaveIntoMissingFolderFails) {
    const fs::path missing = dir_ / "no-such-folder";
    const std::string path = (missing / "field.sdf").string();
    const std::string message = errorFrom([&] { saveFieldText(smallField(), path); });
    EXPECT_CONTAINS(message, path);
    EXPECT_FALSE(fs::exists(missing));
    EXPECT_TRUE(folderContents().empty());
}

TEST_F(FieldText, SaveOverAFolderFailsAndCleansUp) {
    const fs::path folder = dir_ / "field.sdf";
    fs::create_directory(folder);
    const std::string message = errorFrom([&] { saveFieldText(smallField(), folder.string()); });
    EXPECT_CONTAINS(message, folder.string());
    EXPECT_TRUE(fs::is_directory(folder));
    EXPECT_EQ(folderContents(), std::vector<std::string>{"field.sdf"});
}

TEST_F(FieldText, FailedSaveLeavesExistingFileUntouched) {
    const std::string original = "sdfgen-text 1\nthe previous file, byte for byte\n";
    const std::string path = write("field.sdf", original);

    std::vector<std::pair<std::string, Field>> bad;
    {
        Field f = smallField();
        f.values.pop_back();
        bad.emplace_back("too few values", f);
        f.values = {1, 2, 3};
        bad.emplace_back("too many values", f);
    }
    {
        Field f = smallField();
        f.method = "ray casting";
        bad.emplace_back("method with a space", f);
        f.method = "";
        bad.emplace_back("empty method", f);
        f.method = "a=b";
        bad.emplace_back("method with '='", f);
    }
    {
        Field f = smallField();
        f.parameters = {{"rays", "6 4"}};
        bad.emplace_back("parameter value with a space", f);
        f.parameters = {{"", "64"}};
        bad.emplace_back("empty parameter key", f);
        f.parameters = {{"a=b", "64"}};
        bad.emplace_back("parameter key with '='", f);
        f.parameters = {{"rays", ""}};
        bad.emplace_back("empty parameter value", f);
    }
    {
        Field f = smallField();
        f.source = "two\nlines";
        bad.emplace_back("source with a line break", f);
        f.source = "cr\r";
        bad.emplace_back("source with a carriage return", f);
    }
    for (const auto& [what, field] : bad) {
        const std::string message = errorFrom([&, &field = field] { saveFieldText(field, path); });
        EXPECT_CONTAINS(message, path) << what;
        EXPECT_EQ(readBytes(path), original) << what;
        EXPECT_EQ(folderContents(), std::vector<std::string>{"field.sdf"}) << what;
    }
}

TEST_F(FieldText, SaveRejectsFieldsThatCouldNotBeLoaded) {
    // Whatever saveFieldText writes, loadFieldText must read: non-finite values, a non-positive
    // voxel or empty dims must be refused at save time, leaving the existing file alone.
    const std::string original = "previous\n";
    const std::string path = write("field.sdf", original);
    std::vector<std::pair<std::string, Field>> bad;
    {
        Field f = smallField();
        f.values[1] = std::numeric_limits<float>::quiet_NaN();
        bad.emplace_back("NaN value", f);
        f.values[1] = -std::numeric_limits<float>::infinity();
        bad.emplace_back("infinite value", f);
    }
    {
        Field f = smallField();
        f.grid.voxel = 0.0f;
        bad.emplace_back("zero voxel", f);
        f.grid.voxel = std::numeric_limits<float>::quiet_NaN();
        bad.emplace_back("NaN voxel", f);
    }
    {
        Field f = smallField();
        f.grid.origin.y = std::numeric_limits<float>::infinity();
        bad.emplace_back("infinite origin", f);
    }
    {
        Field f = smallField();
        f.grid.dims = {0, 1, 1};
        f.values.clear();
        bad.emplace_back("zero dims", f);
    }
    for (const auto& [what, field] : bad) {
        bool threw = false;
        try {
            saveFieldText(field, path);
        } catch (const Error& e) {
            threw = true;
            EXPECT_CONTAINS(e.what(), path) << what;
        }
        if (!threw) {
            // Not refused: then at least the file written must load.
            EXPECT_NO_THROW(loadFieldText(path)) << what << " was saved but cannot be loaded";
            std::ofstream(path, std::ios::binary) << original;
        }
        EXPECT_EQ(readBytes(path), original) << what;
        expectNoTemporaryFiles();
    }
}

// ---- Field::parameter --------------------------------------------------------------------------

TEST(FieldParameter, Lookup) {
    Field field;
    field.parameters = {{"rays", "64"}, {"seed", "7"}, {"rays", "128"}};
    EXPECT_EQ(field.parameter("rays"), "64"); // the first of duplicates
    EXPECT_EQ(field.parameter("seed"), "7");
    EXPECT_EQ(field.parameter("missing"), "");
    EXPECT_EQ(field.parameter(""), "");
    EXPECT_EQ(field.parameter("RAYS"), "");
    EXPECT_EQ(Field{}.parameter("rays"), "");
}

TEST(FieldParameter, AccessorUsesGridIndex) {
    Field field;
    field.grid.dims = {2, 3, 4};
    for (std::size_t i = 0; i < field.grid.sampleCount(); ++i) field.values.push_back(float(i));
    EXPECT_EQ(field.at(0, 0, 0), 0.0f);
    EXPECT_EQ(field.at(1, 0, 0), 1.0f);
    EXPECT_EQ(field.at(0, 1, 0), 2.0f);
    EXPECT_EQ(field.at(0, 0, 1), 6.0f);
    EXPECT_EQ(field.at(1, 2, 3), 23.0f);
}

} // namespace
} // namespace sdfgen

namespace sdfgen {
namespace {

// A band field and its dense form share one header: the same source, method line, grid and background.
TEST(FieldHeader, SharedByTheDenseAndSparseFields) {
    FieldHeader header;
    header.source = "m.obj";
    header.method = "exact";
    header.parameters = {{"band", "2"}};
    header.grid.dims = {4, 4, 4};
    header.grid.voxel = 0.5;
    header.background = 1.0f;
    const SparseField sparse(header, {}, "m.obj");
    const Field dense = sparse.toDense();
    const FieldHeader& a = sparse.header();
    const FieldHeader& b = dense;
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.parameters, b.parameters);
    EXPECT_TRUE(a.grid.dims == b.grid.dims && a.grid.voxel == b.grid.voxel);
    EXPECT_EQ(a.background, b.background);
    EXPECT_EQ(b.parameter("band"), "2");
    EXPECT_EQ(dense.values, std::vector<float>(64, 1.0f)); // no bricks or inside boxes: all outside
}

// A band field holds together by construction: parts that do not describe a field on the grid are
// refused in one line naming where they came from, and what the field gives back is what it took.
TEST(SparseField, RefusesPartsThatDoNotDescribeAField) {
    FieldHeader header;
    header.grid.dims = {20, 16, 8}; // 3 x 2 x 1 bricks, the last column cut at 20
    header.background = 1.0f;
    const std::vector<float> brick(SparseField::kBrickSamples, 0.5f);
    auto refused = [&](SparseField::Storage storage) {
        try {
            SparseField(header, std::move(storage), "parts.npz");
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("parts.npz: ", 0), 0u) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_CONTAINS(refused({{{0, 0, 0}}, std::vector<float>(100, 0.5f), {}}), "the brick values do not match the bricks");
    EXPECT_CONTAINS(refused({{{0, 0, 0}, {1, 0, 0}}, brick, {}}), "the brick values do not match the bricks");
    EXPECT_CONTAINS(refused({{{3, 0, 0}}, brick, {}}), "brick 0 lies outside the grid");
    std::vector<float> two = brick;
    two.insert(two.end(), brick.begin(), brick.end());
    EXPECT_CONTAINS(refused({{{1, 0, 0}, {0, 0, 0}}, two, {}}), "not in z, y, x order");
    EXPECT_CONTAINS(refused({{{0, 0, 0}}, std::vector<float>(SparseField::kBrickSamples, 2.0f), {}}), "exceeds the background");
    EXPECT_CONTAINS(refused({{}, {}, {{0, 0, 0, 16, 8, 8}, {8, 0, 0, 20, 8, 8}}}), "inside boxes 0 and 1 overlap");
    EXPECT_CONTAINS(refused({{{1, 0, 0}}, brick, {{0, 0, 0, 16, 8, 8}}}), "inside box 0 holds stored brick 0");
    EXPECT_CONTAINS(refused({{}, {}, {{0, 0, 0, 12, 8, 8}}}), "inside box 0 does not hold whole bricks");
    EXPECT_CONTAINS(refused({{}, {}, {{0, 8, 0, 8, 16, 8}, {0, 0, 0, 8, 8, 8}}}), "not in z, y, x order");
    header.background = 0.0f;
    EXPECT_CONTAINS(refused({}), "the band's background is not a positive finite number");

    // Valid parts are taken as they are, and release() takes them back, leaving a field all outside.
    header.background = 1.0f;
    SparseField field(header, {{{1, 0, 0}}, brick, {{16, 0, 0, 20, 8, 8}}}, "parts.npz");
    const float* values = field.values().data();
    EXPECT_EQ(field.at(9, 1, 1), 0.5f);
    EXPECT_EQ(field.at(17, 1, 1), -1.0f);
    EXPECT_EQ(field.at(1, 9, 1), 1.0f);
    const SparseField::Storage taken = field.release();
    EXPECT_EQ(taken.values.data(), values) << "the values were copied";
    EXPECT_TRUE(field.bricks().empty() && field.values().empty() && field.insideBoxes().empty());
    EXPECT_EQ(field.at(17, 1, 1), 1.0f);
}

} // namespace
} // namespace sdfgen
