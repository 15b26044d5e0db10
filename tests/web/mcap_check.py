#!/usr/bin/env python3
"""An independent reader of the MCAP files dynapath log-to-mcap writes: checks
the structure (magic at both ends, every record's length inside the file,
Header first, Data End then Footer last, Schema before its Channel, Channel
before its Messages, per-channel sequence numbers counting from 0, log times
not decreasing per channel), that every message is JSON with the fields its
JSON schema lists, and prints the count of messages per topic.
--last TOPIC OUT writes the last message of TOPIC (its JSON) to OUT.
Usage: mcap_check.py FILE [--expect TOPIC=MIN ...] [--last TOPIC OUT].
Exit 1 with the reason."""
import json
import struct
import sys

MAGIC = b"\x89MCAP0\r\n"


def fail(why):
    print("mcap_check: " + why)
    sys.exit(1)


def string(data, at):
    (n,) = struct.unpack_from("<I", data, at)
    if at + 4 + n > len(data):
        fail("a string runs past its record")
    return data[at + 4:at + 4 + n].decode("utf-8"), at + 4 + n


def main():
    path = sys.argv[1]
    expect = {}
    last = None
    args = sys.argv[2:]
    while args:
        if args[0] == "--expect":
            topic, count = args[1].split("=")
            expect[topic] = int(count)
            args = args[2:]
        elif args[0] == "--last":
            last = (args[1], args[2], None)
            args = args[3:]
        else:
            fail("unknown argument " + args[0])
    data = open(path, "rb").read()
    if data[:8] != MAGIC or data[-8:] != MAGIC:
        fail("no MCAP magic at the start or the end")
    at, end = 8, len(data) - 8
    opcodes, schemas, channels, counts, sequences, times = [], {}, {}, {}, {}, {}
    while at < end:
        if at + 9 > end:
            fail(f"a record header is cut at byte {at}")
        opcode, length = struct.unpack_from("<BQ", data, at)
        body = data[at + 9:at + 9 + length]
        if at + 9 + length > end:
            fail(f"record at byte {at} (opcode {opcode:#x}) runs past the end")
        opcodes.append(opcode)
        if opcode == 0x01:
            profile, k = string(body, 0)
            library, k = string(body, k)
        elif opcode == 0x03:
            (sid,) = struct.unpack_from("<H", body, 0)
            name, k = string(body, 2)
            encoding, k = string(body, k)
            schema, k = string(body, k)
            if encoding != "jsonschema":
                fail("schema encoding " + encoding)
            schemas[sid] = json.loads(schema)
        elif opcode == 0x04:
            cid, sid = struct.unpack_from("<HH", body, 0)
            topic, k = string(body, 4)
            encoding, k = string(body, k)
            (metadata,) = struct.unpack_from("<I", body, k)
            if sid not in schemas:
                fail(f"channel {topic} before its schema {sid}")
            if encoding != "json" or k + 4 + metadata != len(body):
                fail(f"channel {topic}: encoding {encoding} or bad metadata")
            channels[cid] = (topic, schemas[sid])
        elif opcode == 0x05:
            cid, seq, log_time, publish_time = struct.unpack_from("<HIQQ", body, 0)
            if cid not in channels:
                fail(f"message on unknown channel {cid}")
            topic, schema = channels[cid]
            if seq != sequences.get(cid, 0):
                fail(f"{topic}: sequence {seq}, expected {sequences.get(cid, 0)}")
            sequences[cid] = seq + 1
            if log_time < times.get(cid, 0):
                fail(f"{topic}: log time goes back")
            times[cid] = log_time
            message = json.loads(body[22:])
            missing = [f for f in schema["properties"] if f not in message]
            if missing:
                fail(f"{topic}: message lacks {missing}")
            counts[topic] = counts.get(topic, 0) + 1
            if last and last[0] == topic:
                last = (topic, last[1], body[22:])
        elif opcode == 0x0F:
            if length != 4:
                fail("Data End of length %d" % length)
        elif opcode == 0x02:
            if length != 20:
                fail("Footer of length %d" % length)
        else:
            fail(f"unexpected opcode {opcode:#x}")
        at += 9 + length
    if at != end:
        fail("records do not end at the closing magic")
    if not opcodes or opcodes[0] != 0x01 or opcodes[-2:] != [0x0F, 0x02]:
        fail("Header first, Data End and Footer last: got opcodes %s" % opcodes[:3])
    for topic, least in expect.items():
        if counts.get(topic, 0) < least:
            fail(f"{topic}: {counts.get(topic, 0)} messages, expected at least {least}")
    if last:
        if last[2] is None:
            fail(f"no message on {last[0]}")
        open(last[1], "wb").write(last[2])
    print(" ".join(f"{t}={n}" for t, n in sorted(counts.items())))


main()
