#!/usr/bin/env python3
"""Writes the BVH test corpus: one small valid file (bvh_valid/tiny.bvh) and the
malformed files derived from it (bvh_malformed/*.bvh) with EXPECTED.tsv, the
error text each must produce. Generated at build time so the repository
tracks no motion files. Usage: make_bvh_corpus.py OUTDIR"""
import hashlib
import pathlib
import sys

TINY = """HIERARCHY
ROOT Hips
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
\tJOINT Spine
\t{
\t\tOFFSET 0 10 0
\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 0 10 0
\t\t}
\t}
\tJOINT LeftLeg
\t{
\t\tOFFSET 5 -5 0
\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 0 -40 0
\t\t}
\t}
}
MOTION
Frames: 3
Frame Time: 0.0333333
0 90 0 0 0 0 10 0 0 0 0 5
1 90 0 5 0 0 12 0 0 0 0 6
2 90 0 10 0 0 14 0 0 0 0 7
"""


def chain(n, closed, channels="CHANNELS 3 Zrotation Xrotation Yrotation"):
    """A root with n - 1 more joints: siblings when closed, else nested."""
    s = "HIERARCHY\nROOT J0\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
    for i in range(1, n):
        s += "JOINT J%d\n{\nOFFSET 0 1 0\n%s\n%s" % (i, channels, "}\n" if closed else "")
    return s


def cases():
    base = TINY
    m = base.index("MOTION")
    row1 = "1 90 0 5 0 0 12 0 0 0 0 6"
    rot3 = "CHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd"
    yield "trunc_empty_after_hierarchy.bvh", "HIERARCHY\n", "unexpected end of file, expected ROOT"
    yield "trunc_after_root_name.bvh", "HIERARCHY\nROOT Hips\n", "unexpected end of file, expected '{'"
    yield "trunc_in_offset.bvh", "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0", "unexpected end of file, expected OFFSET value"
    yield ("trunc_in_channels.bvh", "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition",
           "unexpected end of file, expected channel name")
    yield "trunc_in_joint.bvh", base[:base.index("End Site")], "unexpected end of file"
    yield "trunc_in_endsite.bvh", base[:base.index("OFFSET 0 10 0\n\t\t}") + 8], "unexpected end of file"
    yield "trunc_before_motion.bvh", base[:m], "no MOTION section"
    yield "trunc_after_motion.bvh", base[:m] + "MOTION\n", "expected 'Frames:'"
    yield "trunc_after_frames.bvh", base[:m] + "MOTION\nFrames: 3\n", "expected 'Frame Time:'"
    yield "trunc_in_frames.bvh", base[:base.index(row1)], "expected 3 frames, found 1"
    yield "trunc_mid_row.bvh", base[:base.index(row1) + 10], "trunc_mid_row.bvh:29: expected 12 channel values, found 5"
    yield ("row_too_short.bvh", base.replace(row1, "1 90 0 5 0 0 12 0 0"),
           "row_too_short.bvh:29: expected 12 channel values, found 9")
    yield "row_too_long.bvh", base.replace(row1, row1 + " 7 8"), "expected 12 channel values, found 14"
    yield ("channels_count_mismatch.bvh", base.replace(rot3, rot3.replace("CHANNELS 3", "CHANNELS 4"), 1),
           "CHANNELS declares 4 channels, found 3")
    yield "channels_count_too_big.bvh", base.replace("CHANNELS 6", "CHANNELS 9"), "count must be between 0 and 6"
    yield ("channels_bad_name.bvh", base.replace("Zrotation Xrotation Yrotation", "Zrotation Wrotation Yrotation", 1),
           "CHANNELS declares 6 channels, found 4 before 'Wrotation'")
    yield ("channels_duplicate.bvh", base.replace("Zrotation Xrotation Yrotation", "Zrotation Zrotation Yrotation", 1),
           "listed twice")
    yield ("channels_two_rotations.bvh",
           base.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 2 Zrotation Xrotation", 1),
           "has 2 rotation channels")
    yield "value_nan.bvh", base.replace("1 90 0 5", "1 90 nan 5"), "value 'nan' is not finite"
    yield "value_inf.bvh", base.replace("1 90 0 5", "1 90 inf 5"), "value 'inf' is not finite"
    yield "value_word.bvh", base.replace("1 90 0 5", "1 90 abc 5"), "expected a number, found 'abc'"
    yield "value_huge.bvh", base.replace("1 90 0 5", "1 90 2e40 5"), "frame 1: value '2e40' is out of range"
    yield "offset_nan.bvh", base.replace("OFFSET 0 10 0", "OFFSET 0 NaN 0", 1), "OFFSET: value 'NaN' is not finite"
    yield "offset_word.bvh", base.replace("OFFSET 0 10 0", "OFFSET 0 ten 0", 1), "OFFSET: expected a number, found 'ten'"
    yield "offset_huge.bvh", base.replace("OFFSET 0 10 0", "OFFSET 0 1e45 0", 1), "OFFSET: value '1e45' is out of range"
    yield "frames_negative.bvh", base.replace("Frames: 3", "Frames: -3"), "Frames: must be positive, found -3"
    yield "frames_zero.bvh", base.replace("Frames: 3", "Frames: 0"), "Frames: must be positive, found 0"
    yield "frames_fraction.bvh", base.replace("Frames: 3", "Frames: 2.5"), "is not a whole number"
    yield "frames_word.bvh", base.replace("Frames: 3", "Frames: three"), "Frames: expected a number, found 'three'"
    yield "frames_more_rows.bvh", base.replace("Frames: 3", "Frames: 2"), "more frame rows than"
    yield ("frame_time_zero.bvh", base.replace("Frame Time: 0.0333333", "Frame Time: 0"),
           "Frame Time: must be a positive number")
    yield ("frame_time_negative.bvh", base.replace("Frame Time: 0.0333333", "Frame Time: -0.01"),
           "Frame Time: must be a positive number")
    yield ("braces_missing_close.bvh", base.replace("\t\t}\n\t}\n\tJOINT LeftLeg", "\t\t}\n\tJOINT LeftLeg", 1),
           "MOTION reached while joint")
    yield ("braces_extra_close.bvh", base.replace("}\nMOTION", "}\n}\nMOTION"),
           "unbalanced braces: '}' after the root joint")
    yield "braces_missing_open.bvh", base.replace("JOINT Spine\n\t{", "JOINT Spine", 1), "expected '{' after joint 'Spine'"
    yield "missing_motion.bvh", base.replace("MOTION\n", "", 1), "expected 'MOTION', found 'Frames:'"
    yield "duplicate_joint.bvh", base.replace("JOINT LeftLeg", "JOINT Spine"), "duplicate joint name 'Spine'"
    yield "absurd_frames.bvh", base.replace("Frames: 3", "Frames: 2000000000"), "exceeds the limit of 10000000 frames"
    yield ("absurd_memory.bvh", chain(200, False) + "}\n" * 200 + "MOTION\nFrames: 9000000\nFrame Time: 0.01\n0 0 0\n",
           "over the limit of 4096 MiB")
    yield ("absurd_joints.bvh", chain(1100, True) + "}\nMOTION\nFrames: 1\nFrame Time: 0.01\n",
           "more than 1024 joints")
    yield "absurd_depth.bvh", chain(300, False, "CHANNELS 0"), "nested deeper than 256"
    yield "empty.bvh", "", "file is empty"
    yield "whitespace_only.bvh", "  \n\t\r\n", "file is empty"
    yield ("not_bvh_text.bvh", "Hello world, this is not a BVH\n",
           "expected 'HIERARCHY' at the start of the file, found 'Hello'")
    junk = b"".join(hashlib.sha256(b"fray-junk-%d" % i).digest() for i in range(128))
    yield "binary_junk.bvh", b"\x01" + junk, "expected 'HIERARCHY'"
    yield ("root_no_channels.bvh",
           base.replace("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n", ""),
           "root joint 'Hips' has no CHANNELS")
    yield ("two_roots.bvh", base.replace("MOTION", "ROOT Other\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION"),
           "more than one ROOT")
    yield "end_site_typo.bvh", base.replace("End Site", "End Sight", 1), "expected 'End Site', found 'End Sight'"
    yield ("offset_twice.bvh", base.replace(rot3, rot3.replace("\t\tEnd", "\t\tOFFSET 1 2 3\n\t\tEnd"), 1),
           "unexpected 'OFFSET'")
    yield "joint_no_name.bvh", base.replace("JOINT Spine", "JOINT ", 1), "joint has no name"
    # Found by fuzz_bvh: "Spine{{" was read as joint "Spine{", which the writer
    # could not write back in a form that reads the same.
    yield "joint_name_brace.bvh", base.replace("JOINT Spine", "JOINT Spine{{", 1), "joint name 'Spine{' contains a brace"
    yield "joint_name_close_brace.bvh", base.replace("JOINT Spine", "JOINT Sp}ine", 1), "joint name 'Sp}ine' contains a brace"


def main():
    out = pathlib.Path(sys.argv[1])
    (out / "bvh_valid").mkdir(parents=True, exist_ok=True)
    (out / "bvh_malformed").mkdir(parents=True, exist_ok=True)
    (out / "bvh_valid" / "tiny.bvh").write_bytes(TINY.encode())
    lines = ['# file\texpected error text (after "FILE:LINE: ")']
    for name, text, expected in cases():
        data = text if isinstance(text, bytes) else text.encode()
        (out / "bvh_malformed" / name).write_bytes(data)
        lines.append(name + "\t" + expected)
    (out / "bvh_malformed" / "EXPECTED.tsv").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
