"""The events of an LCM log, the format lcm-logger and dynapath-recorder
write: per event a sync word, event number, time, channel and data
lengths (big-endian), the channel, the data. For the test scripts.

As a program, `lcm_log.py LOG`: one line per event, "CHANNEL SHA-256 of
the data", sorted (two logs of the same messages print the same lines).
"""
import hashlib
import struct
import sys

SYNC = 0xEDA1DA01
HEADER = struct.Struct(">IqqII")


def events(path):
    """(channel, data) of each event of the log at `path`, in order; an
    assertion fails on a log that is not one or ends inside an event."""
    data = open(path, "rb").read()
    at = 0
    while at < len(data):
        assert at + HEADER.size <= len(data), f"{path}: ends inside an event header"
        sync, _, _, channel_len, data_len = HEADER.unpack_from(data, at)
        assert sync == SYNC, f"{path}: not an LCM log at byte {at}"
        at += HEADER.size
        assert at + channel_len + data_len <= len(data), f"{path}: ends inside an event"
        channel = data[at:at + channel_len].decode()
        at += channel_len
        yield channel, data[at:at + data_len]
        at += data_len


if __name__ == "__main__":
    rows = sorted(f"{channel} {hashlib.sha256(payload).hexdigest()}"
                  for channel, payload in events(sys.argv[1]))
    print("\n".join(rows))
