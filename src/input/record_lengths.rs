//! The lengths inside a record, checked before the `mcap` crate parses it: its parser
//! reserves a string's or a byte array's stated length before reading it, so a flipped
//! byte in the length of a metadata value made it ask for 4 GB to parse a 200-byte record
//! (found by fuzzing). Every length-prefixed field of every record the MCAP specification
//! defines must fit in the bytes left in the record; opcodes it does not define are left
//! to the parser (which keeps them unparsed).
//!
//! Field layouts: <https://mcap.dev/spec> ("Records"); all integers little-endian.

/// Checks the length-prefixed fields of a record with `opcode` and body `data`; the error
/// names the field.
pub fn check_record_lengths(opcode: u8, data: &[u8]) -> Result<(), String> {
    let mut r = Fields { data, at: 0 };
    let checked = match opcode {
        // Header: profile, library.
        0x01 => r.string("profile").and_then(|_| r.string("library")),
        // Schema: id, name, encoding, data (u32 length).
        0x03 => r
            .skip(2, "id")
            .and_then(|_| r.string("name"))
            .and_then(|_| r.string("encoding"))
            .and_then(|_| r.bytes_u32("data")),
        // Channel: id, schema id, topic, message encoding, metadata map.
        0x04 => r
            .skip(4, "ids")
            .and_then(|_| r.string("topic"))
            .and_then(|_| r.string("message_encoding"))
            .and_then(|_| r.string_map("metadata")),
        // Chunk: start, end, uncompressed size, crc, compression, records (u64 length).
        0x06 => r
            .skip(28, "times, size and crc")
            .and_then(|_| r.string("compression"))
            .and_then(|_| r.bytes_u64("records")),
        // Message index: channel id, (time, offset) pairs (u32 byte length).
        0x07 => r.skip(2, "channel_id").and_then(|_| r.bytes_u32("records")),
        // Chunk index: times, offset, length, message index offsets (u32 byte length),
        // message index length, compression, sizes.
        0x08 => r
            .skip(32, "times, offset and length")
            .and_then(|_| r.bytes_u32("message_index_offsets"))
            .and_then(|_| r.skip(8, "message_index_length"))
            .and_then(|_| r.string("compression")),
        // Attachment: times, name, media type, data (u64 length), crc.
        0x09 => r
            .skip(16, "times")
            .and_then(|_| r.string("name"))
            .and_then(|_| r.string("media_type"))
            .and_then(|_| r.bytes_u64("data"))
            .and_then(|_| r.skip(4, "crc")),
        // Attachment index: offset, length, times, data size, name, media type.
        0x0A => r
            .skip(40, "offset, length, times and size")
            .and_then(|_| r.string("name"))
            .and_then(|_| r.string("media_type")),
        // Statistics: counts and times, channel message counts (u32 byte length).
        0x0B => r
            .skip(42, "counts and times")
            .and_then(|_| r.bytes_u32("channel_message_counts")),
        // Metadata: name, metadata map.
        0x0C => r.string("name").and_then(|_| r.string_map("metadata")),
        // Metadata index: offset, length, name.
        0x0D => r
            .skip(16, "offset and length")
            .and_then(|_| r.string("name")),
        // Footer, Message, Summary Offset, Data End: fixed fields (a message's data is
        // the rest of the record); unknown opcodes stay unparsed.
        _ => Ok(()),
    };
    checked.map_err(|e| format!("record with opcode {opcode:#04x}: {e} (corrupted length)"))
}

/// A cursor over a record's body that only checks lengths.
struct Fields<'a> {
    data: &'a [u8],
    at: usize,
}

impl Fields<'_> {
    fn left(&self) -> usize {
        self.data.len() - self.at
    }

    fn skip(&mut self, n: usize, what: &str) -> Result<(), String> {
        if n > self.left() {
            return Err(format!(
                "{what} need {n} bytes, {} are left in the record",
                self.left()
            ));
        }
        self.at += n;
        Ok(())
    }

    fn length(&mut self, width: usize, what: &str) -> Result<u64, String> {
        let start = self.at;
        self.skip(width, what)?;
        let mut le = [0u8; 8];
        le[..width].copy_from_slice(&self.data[start..start + width]);
        Ok(u64::from_le_bytes(le))
    }

    fn prefixed(&mut self, width: usize, what: &str) -> Result<(), String> {
        let n = self.length(width, what)?;
        let left = self.left();
        let n = usize::try_from(n)
            .ok()
            .filter(|&n| n <= left)
            .ok_or_else(|| format!("{what} claims {n} bytes, {left} are left in the record"))?;
        self.at += n;
        Ok(())
    }

    fn string(&mut self, what: &str) -> Result<(), String> {
        self.prefixed(4, what)
    }

    fn bytes_u32(&mut self, what: &str) -> Result<(), String> {
        self.prefixed(4, what)
    }

    fn bytes_u64(&mut self, what: &str) -> Result<(), String> {
        self.prefixed(8, what)
    }

    /// A map of strings: its byte length, then key and value strings within it.
    fn string_map(&mut self, what: &str) -> Result<(), String> {
        let start = self.at + 4;
        self.prefixed(4, what)?;
        let mut entries = Fields {
            data: &self.data[start..self.at],
            at: 0,
        };
        while entries.left() > 0 {
            entries.string(&format!("a key of {what}"))?;
            entries.string(&format!("a value of {what}"))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn string(s: &str) -> Vec<u8> {
        let mut v = (s.len() as u32).to_le_bytes().to_vec();
        v.extend_from_slice(s.as_bytes());
        v
    }

    /// A metadata record body: name, then a map of `pairs`.
    fn metadata(name: &str, pairs: &[(&str, &str)]) -> Vec<u8> {
        let mut map = Vec::new();
        for (k, v) in pairs {
            map.extend(string(k));
            map.extend(string(v));
        }
        let mut body = string(name);
        body.extend((map.len() as u32).to_le_bytes());
        body.extend(map);
        body
    }

    #[test]
    fn whole_records_pass_and_each_mcap_record_parses() {
        let body = metadata("scenario", &[("toml", "seed = 1"), ("x", "")]);
        assert_eq!(check_record_lengths(0x0C, &body), Ok(()));
        assert!(mcap::parse_record(0x0C, &body).is_ok());
        let header = [string("profile"), string("lib")].concat();
        assert_eq!(check_record_lengths(0x01, &header), Ok(()));
    }

    #[test]
    fn a_string_longer_than_its_record_is_refused_before_parsing() {
        let mut body = metadata("scenario", &[("toml", "seed = 1")]);
        // The value's length (the last string: 4 bytes before its 8 characters).
        let at = body.len() - 8 - 4;
        body[at..at + 4].copy_from_slice(&0xFF00_0005u32.to_le_bytes());
        let e = check_record_lengths(0x0C, &body).unwrap_err();
        assert!(
            e.contains("a value of metadata claims 4278190085 bytes"),
            "{e}"
        );
        // The name's length, and the map's.
        let mut body = metadata("scenario", &[]);
        body[0] = 0xFF;
        assert!(check_record_lengths(0x0C, &body).is_err());
        let mut body = metadata("s", &[("k", "v")]);
        body[5] = 0x7F;
        assert!(check_record_lengths(0x0C, &body).is_err());
    }

    #[test]
    fn every_field_of_a_cut_record_is_named() {
        for (opcode, want) in [
            (0x03, "id"),
            (0x04, "ids"),
            (0x06, "times, size and crc"),
            (0x08, "times, offset and length"),
            (0x0B, "counts and times"),
        ] {
            let e = check_record_lengths(opcode, &[0]).unwrap_err();
            assert!(e.contains(want), "{opcode:#x}: {e}");
        }
        // A record with fixed fields only is the parser's to check.
        assert_eq!(check_record_lengths(0x05, &[]), Ok(()));
    }

    /// An attachment without the 4 bytes of its CRC after its data made the `mcap`
    /// parser slice past the record's end (a panic): refused here first.
    #[test]
    fn an_attachment_without_room_for_its_crc_is_refused() {
        let mut body = vec![0u8; 16];
        body.extend(string(""));
        body.extend(string(""));
        body.extend(0u64.to_le_bytes());
        let e = check_record_lengths(0x09, &body).unwrap_err();
        assert!(e.contains("crc need 4 bytes"), "{e}");
        body.extend([0u8; 4]);
        assert_eq!(check_record_lengths(0x09, &body), Ok(()));
        assert!(mcap::parse_record(0x09, &body).is_ok());
    }

    #[test]
    fn the_other_records_with_lengths_are_checked_too() {
        // Message index, attachment index, metadata index: a length past the end.
        let huge = 0xFFFF_FFFFu32.to_le_bytes();
        let cases: [(u8, Vec<u8>, &str); 4] = [
            (0x07, [vec![0, 0], huge.to_vec()].concat(), "records claims"),
            (0x0A, [vec![0; 40], huge.to_vec()].concat(), "name claims"),
            (0x0D, [vec![0; 16], huge.to_vec()].concat(), "name claims"),
            (0x01, huge.to_vec(), "profile claims"),
        ];
        for (opcode, body, want) in cases {
            let e = check_record_lengths(opcode, &body).unwrap_err();
            assert!(e.contains(want), "{opcode:#x}: {e}");
        }
    }
}
