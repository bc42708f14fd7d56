// The viewer's message decoding (apps/view_message.h), apart from the server: what a page may
// send, and the UsageError each malformed message gives (the server closes that connection with
// the message as the reason).
#include <gtest/gtest.h>

#include "core/error.h"
#include "view_message.h"

using namespace ml;

namespace {

void expect_refused(const std::string& text, const std::string& part) {
    SCOPED_TRACE(text);
    try {
        ViewRequest r = decode_view_request(text);
        if (r.kind == ViewRequest::Kind::Settings) apply_view_settings(ViewSettings{}, r.settings);
        ADD_FAILURE() << "accepted";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(ViewMessage, Decodes) {
    ViewRequest v =
        decode_view_request(R"({"type":"view","eye":[0,1,5],"target":[0,1,0],"up":[0,1,0]})");
    EXPECT_EQ(v.kind, ViewRequest::Kind::View);
    EXPECT_EQ(v.look_at, (std::array<float, 9>{0, 1, 5, 0, 1, 0, 0, 1, 0}));
    EXPECT_EQ(decode_view_request(R"({"type":"reset"})").kind, ViewRequest::Kind::Reset);
    EXPECT_EQ(decode_view_request(R"({"type":"save"})").kind, ViewRequest::Kind::Save);
    ViewRequest s = decode_view_request(
        R"({"type":"settings","vpls":512,"interleave":"2x2","exposure":-1.5,"set":"a.b=1"})");
    ASSERT_EQ(s.kind, ViewRequest::Kind::Settings);
    ViewSettings applied = apply_view_settings(ViewSettings{}, s.settings);
    EXPECT_EQ(applied.vpls, 512);
    EXPECT_EQ(applied.interleave, "2x2");
    EXPECT_EQ(applied.exposure, -1.5f);
    EXPECT_EQ(applied.refine_set, "a.b=1");
    EXPECT_EQ(applied.spp, ViewSettings{}.spp);  // members not given stay
}

TEST(ViewMessage, RefusesMalformed) {
    expect_refused("", "not a JSON object");
    expect_refused("[1,2]", "not a JSON object");
    expect_refused(R"({"type":3})", "not a JSON object");
    expect_refused(R"({"type":"jump"})", "unknown message \"jump\"");
    expect_refused(R"({"type":"reset","x":1})", "unknown message \"reset\"");
    expect_refused(R"({"type":"view","eye":[0,1],"target":[0,1,0],"up":[0,1,0]})", "3 numbers");
    expect_refused(R"({"type":"view","eye":[0,1,"5"],"target":[0,1,0],"up":[0,1,0]})", "3 numbers");
    expect_refused(R"({"type":"view","eye":[0,1,5],"target":[0,1,0]})", "3 numbers");
    expect_refused(R"({"type":"view","eye":[0,1,5],"target":[0,1,0],"up":[0,1,0],"x":0})",
                   "unknown members");
    expect_refused(R"({"type":"view","eye":[0,1,1e30],"target":[0,1,0],"up":[0,1,0]})",
                   "out of range");
    expect_refused(R"({"type":"view","eye":[0,1,0],"target":[0,1,0],"up":[0,1,0]})", "must differ");
    expect_refused(R"({"type":"settings","vpls":-1})", "vpls must be a number from 0");
    expect_refused(R"({"type":"settings","spp":"4"})", "spp must be a number");
    expect_refused(R"({"type":"settings","interleave":"4x4x"})", "interleave must be NxM");
    expect_refused(R"({"type":"settings","integrator":"bdpt"})", "integrator must be");
    expect_refused(R"({"type":"settings","set":"nodot=1"})", "expected NAME.KEY=VALUE");
    expect_refused(R"({"type":"settings","colour":1})", "unknown setting \"colour\"");
}
