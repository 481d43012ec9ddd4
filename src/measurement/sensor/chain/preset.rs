//! Sensor presets: datasheet-class parameters of the measurement chain per sensor type.
//!
//! Figures come from docs/sensors.md sections 1-2 and the cited datasheets; those marked
//! *estimate* are engineering estimates, not datasheet values. Accelerometer values are
//! given in g and converted with standard gravity, strain values are in microstrain.

use std::fmt;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Standard acceleration of gravity g_n (CGPM 1901, ISO 80000-3): the g of every
/// accelerometer datasheet. (`crate::base::units::GRAVITY_M_S2` is the rounded 9.81 used for
/// vehicle weights.)
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;

/// Temperature at which a DC-coupled sensor's bias is specified and its drift is zero.
pub const REFERENCE_TEMPERATURE_DEGC: f64 = 20.0;

/// Lowest frequency of the 1/f noise unless overridden: below it the PSD flattens.
/// 1 mHz covers an 11-minute record (1.5 mHz) and the diurnal cycle is drift, not noise.
pub const DEFAULT_FLICKER_LOWEST_HZ: f64 = 1e-3;

const G: f64 = STANDARD_GRAVITY_M_S2;
const MILLI_G: f64 = 1e-3 * G;
const MICRO_G: f64 = 1e-6 * G;

/// What a sensor measures, which decides the unit of every chain parameter:
/// m/s^2 for accelerometers, microstrain for strain gauges, m for displacement, rad for
/// inclinometers, N for load cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TransducerKind {
    Accelerometer,
    Strain,
    Displacement,
    Inclinometer,
    LoadCell,
    Thermometer,
}

impl TransducerKind {
    /// The kind named `name` (`"accelerometer"`, `"strain"`, `"displacement"`); the error
    /// names `field`.
    pub fn parse(name: &str, field: &str) -> Result<Self> {
        match name {
            "accelerometer" => Ok(Self::Accelerometer),
            "strain" => Ok(Self::Strain),
            "displacement" => Ok(Self::Displacement),
            "inclinometer" => Ok(Self::Inclinometer),
            "load_cell" => Ok(Self::LoadCell),
            "thermometer" => Ok(Self::Thermometer),
            _ => Err(Error::invalid(
                field,
                name,
                "is not a sensor kind (accelerometer, strain, displacement, inclinometer, \
                 load_cell, thermometer)",
            )),
        }
    }

    /// The snake_case name, as in a scenario.
    pub fn name(self) -> &'static str {
        match self {
            Self::Accelerometer => "accelerometer",
            Self::Strain => "strain",
            Self::Displacement => "displacement",
            Self::Inclinometer => "inclinometer",
            Self::LoadCell => "load_cell",
            Self::Thermometer => "thermometer",
        }
    }
}

/// A sensor type with datasheet-class chain parameters (the table is in docs/sensors.md
/// section 1.1).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SensorPreset {
    /// Every stage off: the anti-aliased true response. For all kinds. The default.
    #[default]
    Ideal,
    /// Low-noise MEMS accelerometer, ADXL355 class.
    MemsLownoise,
    /// Seismic piezoelectric (IEPE) accelerometer, PCB 393B04 class, on a 24-bit DAQ.
    PiezoSeismic,
    /// Force-balance accelerometer, Kinemetrics EpiSensor class, on a 24-bit DAQ.
    ForceBalance,
    /// Consumer MEMS accelerometer, ADXL345 class.
    MemsConsumer,
    /// Foil strain gauge in a quarter bridge on a 24-bit DAQ.
    StrainFoil,
    /// MEMS inclinometer at a bearing, Murata SCL3300 class.
    InclinometerMems,
    /// 5 MN strain-gauge load cell under a bearing, on a 24-bit bridge amplifier.
    LoadCellBearing,
    /// Pt100 class A resistance thermometer on the deck, 24-bit RTD input.
    ThermometerPt100,
}

impl fmt::Display for SensorPreset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A value that is either fixed or drawn once per sensor from `N(0, sigma^2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Draw {
    Fixed(f64),
    Normal { sigma: f64 },
}

/// The transfer function of the sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Coupling {
    /// AC-coupled: first-order high-pass with -3 dB at `highpass_hz`; no DC output.
    Ac { highpass_hz: f64 },
    /// DC-coupled: output `x + bias + bias_tempco_per_degc * (T - 20 degC)`, in the
    /// channel's unit.
    Dc {
        bias: Draw,
        bias_tempco_per_degc: f64,
    },
}

/// Mains hum added before the anti-alias filter (electromagnetic pick-up on the cable).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HumParameters {
    /// 50 Hz (Europe) or 60 Hz (Americas); any positive value accepted.
    pub frequency_hz: f64,
    /// Peak amplitude in the channel's unit, before the anti-alias filter.
    pub amplitude: f64,
    /// Phase at t = 0; `None`: uniform in [0, 2 pi), drawn once per sensor.
    pub phase_rad: Option<f64>,
}

/// Analog-to-digital converter: `bits` over `[-range, range)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdcParameters {
    /// Resolution, 1..=32.
    pub bits: u32,
    /// Full scale in the channel's unit: codes span `[-range, range - lsb]`.
    pub range: f64,
}

impl AdcParameters {
    /// Quantisation step `2 range / 2^bits`.
    pub fn lsb(&self) -> f64 {
        2.0 * self.range / 2f64.powi(self.bits as i32)
    }
}

/// Every parameter of a chain, in the channel's unit (see [`TransducerKind`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainParameters {
    pub coupling: Coupling,
    /// Relative gain (sensitivity) error: output `x (1 + gain_error)`.
    pub gain_error: Draw,
    /// White self-noise, one-sided amplitude density, unit/sqrt(Hz).
    pub noise_density: f64,
    /// 1/f corner: the PSD is `noise_density^2 (1 + flicker_corner_hz / f)`; 0 = white.
    pub flicker_corner_hz: f64,
    /// Lowest frequency of the 1/f part, Hz.
    pub flicker_lowest_hz: f64,
    pub hum: Option<HumParameters>,
    pub adc: Option<AdcParameters>,
    /// Highest output rate the sensor or its DAQ supports; `None`: no limit.
    pub max_rate_hz: Option<f64>,
}

impl SensorPreset {
    /// Every preset, in declaration order.
    pub const ALL: [SensorPreset; 9] = [
        Self::Ideal,
        Self::MemsLownoise,
        Self::PiezoSeismic,
        Self::ForceBalance,
        Self::MemsConsumer,
        Self::StrainFoil,
        Self::InclinometerMems,
        Self::LoadCellBearing,
        Self::ThermometerPt100,
    ];

    /// The snake_case name, as in a scenario.
    pub fn name(self) -> &'static str {
        match self {
            Self::Ideal => "ideal",
            Self::MemsLownoise => "mems_lownoise",
            Self::PiezoSeismic => "piezo_seismic",
            Self::ForceBalance => "force_balance",
            Self::MemsConsumer => "mems_consumer",
            Self::StrainFoil => "strain_foil",
            Self::InclinometerMems => "inclinometer_mems",
            Self::LoadCellBearing => "load_cell_bearing",
            Self::ThermometerPt100 => "thermometer_pt100",
        }
    }

    /// The one kind the preset is for; `None` for [`SensorPreset::Ideal`] (every kind).
    pub fn kind(self) -> Option<TransducerKind> {
        match self {
            Self::Ideal => None,
            Self::StrainFoil => Some(TransducerKind::Strain),
            Self::InclinometerMems => Some(TransducerKind::Inclinometer),
            Self::LoadCellBearing => Some(TransducerKind::LoadCell),
            Self::ThermometerPt100 => Some(TransducerKind::Thermometer),
            _ => Some(TransducerKind::Accelerometer),
        }
    }

    /// Errors naming `field` (the scenario's `preset`) when the preset is not for `kind`.
    pub fn check_kind(self, kind: TransducerKind, field: &str) -> Result<()> {
        match self.kind() {
            Some(k) if k != kind => Err(Error::invalid(
                field,
                self,
                format!(
                    "is a preset for {} sensors, not for {} sensors (use ideal or a {} preset)",
                    k.name(),
                    kind.name(),
                    kind.name()
                ),
            )),
            _ => Ok(()),
        }
    }

    /// The preset's chain, in the unit of its kind (m/s^2, microstrain; `Ideal` is
    /// unit-free since every stage is off).
    pub fn parameters(self) -> ChainParameters {
        match self {
            Self::Ideal => ideal(),
            Self::MemsLownoise => mems_lownoise(),
            Self::PiezoSeismic => piezo_seismic(),
            Self::ForceBalance => force_balance(),
            Self::MemsConsumer => mems_consumer(),
            Self::StrainFoil => strain_foil(),
            Self::InclinometerMems => inclinometer_mems(),
            Self::LoadCellBearing => load_cell_bearing(),
            Self::ThermometerPt100 => thermometer_pt100(),
        }
    }
}

fn ideal() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Fixed(0.0),
            bias_tempco_per_degc: 0.0,
        },
        gain_error: Draw::Fixed(0.0),
        noise_density: 0.0,
        flicker_corner_hz: 0.0,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: None,
        max_rate_hz: None,
    }
}

/// ADXL355 (Analog Devices data sheet Rev. D): 22.5 ug/sqrt(Hz); 20-bit output at
/// +/-2.048 g, 3.9 ug/LSB; DC-coupled; 0 g offset vs temperature 0.15 mg/degC maximum,
/// of which a typical unit shows about two thirds: 0.1 mg/degC (estimate); output data
/// rate up to 4000 Hz. Initial offset sigma 10 mg (estimate, the data sheet's +/-25 mg
/// taken as 2.5 sigma); sensitivity sigma 1 % (estimate); 1/f corner 0.05 Hz (estimate).
/// The internal low-pass at ODR/4 is not modelled: the channel's anti-alias filter is
/// the only low-pass.
fn mems_lownoise() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Normal {
                sigma: 10.0 * MILLI_G,
            },
            bias_tempco_per_degc: 0.1 * MILLI_G,
        },
        gain_error: Draw::Normal { sigma: 0.01 },
        noise_density: 22.5 * MICRO_G,
        flicker_corner_hz: 0.05,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 20,
            range: 2.048 * G,
        }),
        max_rate_hz: Some(4000.0),
    }
}

/// PCB 393B04 class: AC-coupled, -3 dB at 0.06 Hz; ~3 ug rms broadband (docs/sensors.md,
/// estimate) modelled as 0.12 ug/sqrt(Hz) white with a 10 Hz 1/f corner (estimate):
/// over 0.06..450 Hz that is `0.12 sqrt(450 + 10 ln(450 / 0.06))` = 2.8 ug rms. Range
/// +/-5 g (the sensor's, 1 V/g into a +/-5 V 24-bit DAQ). Calibrated sensitivity sigma 1 %
/// (estimate). Maximum rate 2000 Hz (estimate: DAQ setting for a 450 Hz sensor).
fn piezo_seismic() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Ac { highpass_hz: 0.06 },
        gain_error: Draw::Normal { sigma: 0.01 },
        noise_density: 0.12 * MICRO_G,
        flicker_corner_hz: 10.0,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 24,
            range: 5.0 * G,
        }),
        max_rate_hz: Some(2000.0),
    }
}

/// Kinemetrics EpiSensor class: DC-coupled, DC..200 Hz, clip selectable 0.25..4 g, here
/// +/-2 g on 24 bits. The sensor's own 155 dB dynamic range puts its noise below what the
/// 24-bit DAQ resolves, so the noise is the DAQ's: ~130 dB over 100 Hz below a 2 g full
/// scale sine (1.41 g rms) gives 1.41 g / 10^6.5 / sqrt(100 Hz) = 0.045, rounded to
/// 0.05 ug/sqrt(Hz) (estimate). Zero offset adjusted at installation (bias 0); offset
/// drift 0.05 mg/degC, sensitivity sigma 1 %, 1/f corner 0.1 Hz, maximum rate 2000 Hz
/// (all estimates).
fn force_balance() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Fixed(0.0),
            bias_tempco_per_degc: 0.05 * MILLI_G,
        },
        gain_error: Draw::Normal { sigma: 0.01 },
        noise_density: 0.05 * MICRO_G,
        flicker_corner_hz: 0.1,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 24,
            range: 2.0 * G,
        }),
        max_rate_hz: Some(2000.0),
    }
}

/// ADXL345 (Analog Devices data sheet Rev. E): noise density 290 ug/sqrt(Hz) (x, y) to
/// 430 ug/sqrt(Hz) (z), here 350; full resolution 13 bit at +/-16 g (3.9 mg/LSB); output
/// data rate up to 3200 Hz; sensitivity 230..282 LSB/g around 256 (+/-10 %, taken as
/// 3 sigma: 3.3 %). 1/f corner from the data sheet's Allan-deviation floor of ~100 ug:
/// for `S = h / f`, `sigma_A = sqrt(2 ln 2 h)`, so with `h = ND^2 fc`,
/// `fc = 100^2 / (2 ln 2 350^2)` = 0.06 Hz. Initial offset sigma 40 mg and offset drift
/// 0.8 mg/degC (estimates of the data sheet's order of magnitude).
fn mems_consumer() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Normal {
                sigma: 40.0 * MILLI_G,
            },
            bias_tempco_per_degc: 0.8 * MILLI_G,
        },
        gain_error: Draw::Normal { sigma: 0.033 },
        noise_density: 350.0 * MICRO_G,
        flicker_corner_hz: 0.06,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 13,
            range: 16.0 * G,
        }),
        max_rate_hz: Some(3200.0),
    }
}

/// Foil gauge, quarter bridge, 24-bit DAQ (docs/sensors.md section 2, estimates): 0.2..1 ue rms
/// at ~1 kHz; taking 0.5 ue rms over the 500 Hz band of a 1 kHz record gives
/// 0.5 / sqrt(500) = 0.0224 ue/sqrt(Hz). Apparent thermal strain 1..2 ue/degC: 1.5.
/// Gauge-factor tolerance +/-1 % (foil gauge data sheets), used as sigma. Bridge balanced
/// at installation (bias 0). Range +/-3000 ue, maximum rate 10 kHz, 1/f corner 1 Hz
/// (DC-excited bridge amplifier; estimate).
fn strain_foil() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Fixed(0.0),
            bias_tempco_per_degc: 1.5,
        },
        gain_error: Draw::Normal { sigma: 0.01 },
        noise_density: 0.5 / 500f64.sqrt(),
        flicker_corner_hz: 1.0,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 24,
            range: 3000.0,
        }),
        max_rate_hz: Some(10_000.0),
    }
}

/// Murata SCL3300-D01 class MEMS inclinometer (data sheet features; sister die SCA3300
/// data sheet Doc.No. 3165 rev. 3, table 2): 0.001 deg/sqrt(Hz) = 1.75e-5 rad/sqrt(Hz);
/// offset change over -40..+125 degC +/-10 mg = 0.57 deg (3 sigma) over about 100 K:
/// 3.3e-5 rad/degC as sigma, here the tempco of a typical unit (estimate); sensitivity
/// +/-0.7 % (3 sigma): 0.23 %; zeroed at installation, residual bias sigma 1e-4 rad
/// (0.005 deg, the accuracy of packaged MEMS tiltmeters: Worldsensing Tilt90 data sheet);
/// output data rate 2000 Hz. The angle output is 16 bits over +/-180 deg (0.0055 deg =
/// 9.6e-5 rad per LSB): a bearing's rotation under traffic (1e-4 rad) spans about one
/// LSB, which is what such a sensor records (a staircase that averaging over minutes
/// resolves). 1/f corner 0.02 Hz (estimate: no data sheet figure).
fn inclinometer_mems() -> ChainParameters {
    const DEG: f64 = std::f64::consts::PI / 180.0;
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Normal { sigma: 1e-4 },
            bias_tempco_per_degc: 3.3e-5,
        },
        gain_error: Draw::Normal { sigma: 0.0023 },
        noise_density: 0.001 * DEG,
        flicker_corner_hz: 0.02,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 16,
            range: 180.0 * DEG,
        }),
        max_rate_hz: Some(2000.0),
    }
}

/// A 5 MN strain-gauge compression load cell under a bearing (2 mV/V), on a 24-bit
/// delta-sigma bridge amplifier. Zero tempco: modern cells below 0.05 % of full scale per
/// 10 K (HBM, "temperature coefficient of the zero point"): 250 N/degC as a limit, 125
/// as a typical unit (estimate). Noise: TI ADS1232 application example, about 18 nV rms
/// at 10 samples/s on a 10 mV full-scale signal, 1.8e-6 of full scale: 9 N rms over
/// about 5 Hz, 4 N/sqrt(Hz). Calibrated sensitivity sigma 0.1 % (precision cells
/// +/-0.1..0.2 %); zeroed under dead load at installation, residual zero sigma 0.05 % of
/// full scale, 2.5 kN (creep and drift; estimate). ADC 24 bits over +/-5 MN (0.6 N per
/// LSB). Maximum rate 1000 Hz (bridge amplifiers of the HBM QuantumX class sample up to
/// 19.2 kHz; the cell's own bandwidth, estimate). 1/f corner 0.05 Hz (estimate).
fn load_cell_bearing() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Normal { sigma: 2.5e3 },
            bias_tempco_per_degc: 125.0,
        },
        gain_error: Draw::Normal { sigma: 0.001 },
        noise_density: 4.0,
        flicker_corner_hz: 0.05,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 24,
            range: 5e6,
        }),
        max_rate_hz: Some(1000.0),
    }
}

/// Pt100 resistance thermometer, tolerance class A of IEC 60751: +/-(0.15 + 0.002 |t|) degC,
/// at bridge temperatures about +/-0.19 degC, taken as 2 sigma of a fixed offset: 0.1 degC
/// (the bias); its gain error is in that tolerance (0). Read by a 24-bit RTD input:
/// 0.005 degC rms over a few Hz (estimate of 24-bit RTD modules' resolution), so 2e-3
/// degC/sqrt(Hz). Range +/-200 degC; rate up to 100 Hz (RTD modules sample slowly; bridge
/// monitoring logs temperatures at minutes, any rate the channel accepts works). No
/// drift with the air temperature: the temperature is the measurand.
fn thermometer_pt100() -> ChainParameters {
    ChainParameters {
        coupling: Coupling::Dc {
            bias: Draw::Normal { sigma: 0.1 },
            bias_tempco_per_degc: 0.0,
        },
        gain_error: Draw::Fixed(0.0),
        noise_density: 2e-3,
        flicker_corner_hz: 0.0,
        flicker_lowest_hz: DEFAULT_FLICKER_LOWEST_HZ,
        hum: None,
        adc: Some(AdcParameters {
            bits: 24,
            range: 200.0,
        }),
        max_rate_hz: Some(100.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adxl_resolutions_match_their_data_sheets() {
        // ADXL355 3.9 ug/LSB at +/-2.048 g, ADXL345 3.9 mg/LSB at +/-16 g full resolution:
        // both exact to the quoted two digits.
        let lsb = |p: SensorPreset| p.parameters().adc.map(|a| a.lsb() / G);
        let adxl355 = lsb(SensorPreset::MemsLownoise).unwrap_or(0.0);
        assert!((adxl355 / 3.9e-6 - 1.0).abs() < 0.005, "{adxl355}");
        let adxl345 = lsb(SensorPreset::MemsConsumer).unwrap_or(0.0);
        assert!((adxl345 / 3.9e-3 - 1.0).abs() < 0.005, "{adxl345}");
    }

    #[test]
    fn presets_are_for_their_kind_only() {
        use TransducerKind::*;
        for p in SensorPreset::ALL {
            for kind in [
                Accelerometer,
                Strain,
                Displacement,
                Inclinometer,
                LoadCell,
                Thermometer,
            ] {
                let ok = p.check_kind(kind, "sensors.0.preset").is_ok();
                let expected = match p {
                    SensorPreset::Ideal => true,
                    SensorPreset::StrainFoil => kind == Strain,
                    SensorPreset::InclinometerMems => kind == Inclinometer,
                    SensorPreset::LoadCellBearing => kind == LoadCell,
                    SensorPreset::ThermometerPt100 => kind == Thermometer,
                    _ => kind == Accelerometer,
                };
                assert_eq!(ok, expected, "{p} on {kind:?}");
            }
        }
        let e = SensorPreset::StrainFoil
            .check_kind(Accelerometer, "sensors.3.preset")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("sensors.3.preset = strain_foil is a preset for strain"),
            "{e}"
        );
    }

    #[test]
    fn kinds_parse_by_name() {
        for kind in [
            TransducerKind::Accelerometer,
            TransducerKind::Strain,
            TransducerKind::Displacement,
            TransducerKind::Inclinometer,
            TransducerKind::LoadCell,
            TransducerKind::Thermometer,
        ] {
            assert_eq!(TransducerKind::parse(kind.name(), "k").ok(), Some(kind));
        }
        let e = TransducerKind::parse("tilt", "sensors.1.kind").unwrap_err();
        assert!(
            e.to_string().starts_with("sensors.1.kind = tilt is not"),
            "{e}"
        );
    }
}
