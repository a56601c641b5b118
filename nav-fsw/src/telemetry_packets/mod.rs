//! Telemetry packets: a frame's output record (`crate::replay::output_words`) as CCSDS Space
//! Packets (the CCSDS Space Packet Protocol, blue book 133.0), one APID per packet kind, each
//! kind at its own rate, for a ground system to decode. The layout is one declaration ([`PACKETS`]);
//! docs/reference/telemetry-packets.md is generated from it.
//!
//! A packet, every field big-endian (CCSDS transmits the most significant bit first):
//!
//! | bytes | field |
//! |---|---|
//! | 0..6 | primary header: version `000`, type 0 (telemetry), secondary header flag 1, the kind's 11-bit APID; sequence flags `11` (unsegmented), the kind's 14-bit sequence count (wraps); data length = bytes after the primary header − 1 |
//! | 6..22 | secondary header: the frame counter (`u64`) and the navigation time (`f64`, s): the output words `frame` and `time_s` |
//! | 22.. | the kind's output words ([`PacketDeclaration::words`]), each a `u64` or `f64` |
//! | last 2 | packet error control, as the ECSS PUS (ECSS-E-ST-70-41C) has it: CRC-16/CCITT-FALSE (polynomial `0x1021`, initial `0xFFFF`) of every byte before it |
//!
//! The packets of one frame have the same secondary header; a kind is sent in the frames
//! whose counter is a multiple of its rate ([`PacketRates`]).
//!
//! The encoder is written here rather than taken from a crate: the flight path needs an
//! encoder without allocation and without a panic path, and the Rust CCSDS crates
//! (`spacepackets`) build their headers from range-checked integer types whose constructors
//! panic out of range. The ground decoder (nav-sim) reads the primary header with
//! `spacepackets`, an independent implementation of the standard.

mod declaration;
#[cfg(test)]
mod tests;

pub use declaration::{
    word_type, PacketDeclaration, PacketKind, WordSpan, WordType, MAX_DATA_WORDS,
    MAX_FRAME_PACKET_BYTES, PACKETS, PACKET_KIND_COUNT,
};

use crc::{Crc, CRC_16_IBM_3740};

use crate::replay::OUTPUT_WORDS;

/// Bytes of the primary header.
pub const PRIMARY_HEADER_BYTES: usize = 6;
/// Bytes of the secondary header: the frame counter and the navigation time.
pub const SECONDARY_HEADER_BYTES: usize = 16;
/// The output words of the secondary header: `frame`, `time_s`.
pub const SECONDARY_HEADER_WORDS: core::ops::Range<usize> = 0..2;
/// Bytes of the packet error control.
pub const CRC_BYTES: usize = 2;
/// Sequence counts wrap at 2¹⁴.
pub const SEQUENCE_COUNT_MODULUS: u16 = 1 << 14;
/// The largest rate: a kind sent once every this many frames at the least.
pub const MAX_RATE_FRAMES: u32 = 1 << 16;

/// The packet error control's CRC: CRC-16/CCITT-FALSE (`CRC_16_IBM_3740` in the `crc` crate).
pub const PACKET_CRC: Crc<u16> = Crc::<u16>::new(&CRC_16_IBM_3740);

/// Why a packet could not be encoded or a rate was refused (nothing is written or changed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PacketError {
    /// The caller's buffer is smaller than the packets need.
    BufferTooSmall {
        /// Bytes needed.
        needed: usize,
        /// Bytes given.
        available: usize,
    },
    /// A rate outside `1..=MAX_RATE_FRAMES` frames.
    Rate {
        /// The kind.
        kind: PacketKind,
        /// The rate asked for (frames).
        every_frames: u32,
    },
}

impl core::fmt::Display for PacketError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::BufferTooSmall { needed, available } => write!(
                f,
                "telemetry packet buffer too small: {needed} bytes needed, {available} given"
            ),
            Self::Rate { kind, every_frames } => write!(
                f,
                "telemetry rate of `{}` packets refused: every {every_frames} frames, \
                 accepted 1 to {MAX_RATE_FRAMES}",
                kind.declaration().name
            ),
        }
    }
}

impl core::error::Error for PacketError {}

/// Every kind's rate: sent in the frames whose counter is a multiple of it (1: every frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PacketRates {
    every_frames: [u32; PACKET_KIND_COUNT],
}

impl PacketRates {
    /// Every kind in every frame.
    pub const EVERY_FRAME: Self = Self {
        every_frames: [1; PACKET_KIND_COUNT],
    };

    /// Rates in [`PacketKind::ALL`] order.
    ///
    /// # Errors
    /// [`PacketError::Rate`] naming the first kind whose rate is outside
    /// `1..=MAX_RATE_FRAMES`.
    pub fn new(every_frames: [u32; PACKET_KIND_COUNT]) -> Result<Self, PacketError> {
        let mut rates = Self::EVERY_FRAME;
        for (kind, rate) in PacketKind::ALL.into_iter().zip(every_frames) {
            rates.set(kind, rate)?;
        }
        Ok(rates)
    }

    /// Sets one kind's rate.
    ///
    /// # Errors
    /// [`PacketError::Rate`] for a rate outside `1..=MAX_RATE_FRAMES`; unchanged then.
    pub fn set(&mut self, kind: PacketKind, every_frames: u32) -> Result<(), PacketError> {
        if !(1..=MAX_RATE_FRAMES).contains(&every_frames) {
            return Err(PacketError::Rate { kind, every_frames });
        }
        if let Some(slot) = self.every_frames.get_mut(kind.index()) {
            *slot = every_frames;
        }
        Ok(())
    }

    /// The kind's rate (frames).
    pub fn every_frames(&self, kind: PacketKind) -> u32 {
        self.every_frames.get(kind.index()).copied().unwrap_or(1)
    }

    /// Whether `kind` is sent in the frame counted `frame`.
    pub fn due(&self, kind: PacketKind, frame: u64) -> bool {
        frame % u64::from(self.every_frames(kind).max(1)) == 0
    }
}

impl Default for PacketRates {
    fn default() -> Self {
        Self::EVERY_FRAME
    }
}

/// Encodes frames' output records as packets, keeping each APID's sequence count.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PacketEncoder {
    rates: PacketRates,
    sequence_counts: [u16; PACKET_KIND_COUNT],
}

impl PacketEncoder {
    /// An encoder whose sequence counts start at 0.
    pub const fn new(rates: PacketRates) -> Self {
        Self {
            rates,
            sequence_counts: [0; PACKET_KIND_COUNT],
        }
    }

    /// The rates.
    pub const fn rates(&self) -> &PacketRates {
        &self.rates
    }

    /// The sequence count the next packet of `kind` carries.
    pub fn next_sequence_count(&self, kind: PacketKind) -> u16 {
        self.sequence_counts.get(kind.index()).copied().unwrap_or(0)
    }

    /// Writes the packets due in the frame of `words` (its `frame` word), in
    /// [`PacketKind::ALL`] order, at the start of `buffer`; returns the bytes written.
    /// [`MAX_FRAME_PACKET_BYTES`] is always enough.
    ///
    /// # Errors
    /// [`PacketError::BufferTooSmall`] if the due packets do not fit; nothing is written and
    /// the sequence counts are unchanged then.
    pub fn encode_frame(
        &mut self,
        words: &[u64; OUTPUT_WORDS],
        buffer: &mut [u8],
    ) -> Result<usize, PacketError> {
        let frame = words.first().copied().unwrap_or(0);
        let due = PacketKind::ALL.map(|kind| self.rates.due(kind, frame));
        let needed: usize = PACKETS
            .iter()
            .zip(due)
            .filter(|(_, due)| *due)
            .map(|(packet, _)| packet.packet_bytes())
            .sum();
        if needed > buffer.len() {
            return Err(PacketError::BufferTooSmall {
                needed,
                available: buffer.len(),
            });
        }
        let mut written = 0;
        for (kind, _) in PacketKind::ALL.into_iter().zip(due).filter(|(_, due)| *due) {
            let rest = buffer.get_mut(written..).unwrap_or_default();
            written += self.encode(kind, words, rest)?;
        }
        Ok(written)
    }

    /// Writes the packet of `kind` for the frame of `words` at the start of `buffer`, whether
    /// due or not; returns its length ([`PacketDeclaration::packet_bytes`]).
    ///
    /// # Errors
    /// [`PacketError::BufferTooSmall`]; nothing is written and the kind's sequence count is
    /// unchanged then.
    pub fn encode(
        &mut self,
        kind: PacketKind,
        words: &[u64; OUTPUT_WORDS],
        buffer: &mut [u8],
    ) -> Result<usize, PacketError> {
        let declaration = kind.declaration();
        let length = declaration.packet_bytes();
        let available = buffer.len();
        let Some(packet) = buffer.get_mut(..length) else {
            return Err(PacketError::BufferTooSmall {
                needed: length,
                available,
            });
        };
        let count = self.next_sequence_count(kind);
        let (body, crc) = packet.split_at_mut(length.saturating_sub(CRC_BYTES));
        let mut slots = body.iter_mut();
        // The chunk drives the zip: it is asked first, so its end takes no slot.
        let mut put = |chunk: &[u8]| {
            for (byte, slot) in chunk.iter().zip(slots.by_ref()) {
                *slot = *byte;
            }
        };
        put(&primary_header(declaration.apid, count, length));
        for index in SECONDARY_HEADER_WORDS {
            put(&words.get(index).copied().unwrap_or(0).to_be_bytes());
        }
        for index in declaration.words.iter().flat_map(WordSpan::indices) {
            put(&words.get(index).copied().unwrap_or(0).to_be_bytes());
        }
        let checksum = PACKET_CRC.checksum(body);
        for (slot, byte) in crc.iter_mut().zip(checksum.to_be_bytes()) {
            *slot = byte;
        }
        if let Some(slot) = self.sequence_counts.get_mut(kind.index()) {
            *slot = (count + 1) % SEQUENCE_COUNT_MODULUS;
        }
        Ok(length)
    }
}

/// The primary header (module docs) of a telemetry packet of `length` bytes.
fn primary_header(apid: u16, sequence_count: u16, length: usize) -> [u8; PRIMARY_HEADER_BYTES] {
    // Version 000, type 0 (telemetry), secondary header flag 1, APID (11 bits).
    let identification = (1 << 11) | (apid & 0x07FF);
    // Sequence flags 11 (unsegmented), sequence count (14 bits).
    let sequence = (0b11 << 14) | (sequence_count % SEQUENCE_COUNT_MODULUS);
    // Data length: octets after the primary header, minus one (Space Packet Protocol
    // §4.1.3.5). The longest packet is far below 2¹⁶ octets.
    let data_length =
        u16::try_from(length.saturating_sub(PRIMARY_HEADER_BYTES + 1)).unwrap_or(u16::MAX);
    let [i0, i1] = identification.to_be_bytes();
    let [s0, s1] = sequence.to_be_bytes();
    let [l0, l1] = data_length.to_be_bytes();
    [i0, i1, s0, s1, l0, l1]
}
