// The progress of long work where no terminal shows a bar (a log, CI, a pipe): a line with the
// count, the time so far and the time left, no more often than asked, and none for work that
// ends first.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <thread>

#include "core/progress.h"

namespace aquaform {
namespace {

std::string contents(std::FILE* f) {
    std::fflush(f);
    std::rewind(f);
    std::string text;
    for (int c; (c = std::fgetc(f)) != EOF;) text += char(c);
    return text;
}

TEST(ProgressLog, LongWorkSaysHowFarItIsAndHowLongItWillTake) {
    std::FILE* log = std::tmpfile();
    ASSERT_NE(log, nullptr);
    {
        ProgressBar progress("simulating to frame 999999", 999999, log, false, std::chrono::milliseconds(20));
        progress.update(1);  // too soon: nothing yet
        EXPECT_EQ(contents(log), "");
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        progress.update(3);
        progress.update(4);  // within the interval again: no second line
        progress.finish();
    }
    const std::string text = contents(log);
    EXPECT_EQ(text.rfind("simulating to frame 999999: 3 of 999999, ", 0), 0u) << text;
    EXPECT_NE(text.find("left"), std::string::npos) << text;
    EXPECT_NE(text.find('h'), std::string::npos) << "a million frames at this rate take hours: " << text;
    EXPECT_EQ(text.find('\n'), text.size() - 1) << "one line: " << text;
    std::fclose(log);
}

TEST(ProgressLog, ShortWorkWritesNothing) {
    std::FILE* log = std::tmpfile();
    ASSERT_NE(log, nullptr);
    {
        ProgressBar progress("frames", 3, log, false, std::chrono::seconds(10));
        for (int k = 1; k <= 3; ++k) progress.update(k);
        progress.finish();
    }
    EXPECT_EQ(contents(log), "");
    std::fclose(log);
}

}  // namespace
}  // namespace aquaform
