//! Choosing burn's CPU device at run time. burn 0.22 tensors are not generic over a backend:
//! the device decides. `flex` is the default (burn's recommended CPU backend); `ndarray` is
//! kept selectable because the user asked for it (it is deprecated upstream and slower, see
//! BENCHMARKS.md).

use std::str::FromStr;

use burn::tensor::Device;
use serde::{Deserialize, Serialize};

use crate::error::XylemError;

/// Which CPU backend runs the tensors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DeviceKind {
    #[default]
    Flex,
    Ndarray,
}

impl DeviceKind {
    /// The burn device without gradients.
    pub fn device(self) -> Device {
        match self {
            DeviceKind::Flex => Device::flex(),
            #[allow(deprecated)]
            DeviceKind::Ndarray => Device::ndarray(),
        }
    }

    /// The burn device with autodiff enabled.
    pub(crate) fn autodiff_device(self) -> Device {
        self.device().autodiff()
    }

    pub fn name(self) -> &'static str {
        match self {
            DeviceKind::Flex => "flex",
            DeviceKind::Ndarray => "ndarray",
        }
    }
}

impl FromStr for DeviceKind {
    type Err = XylemError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "flex" => Ok(DeviceKind::Flex),
            "ndarray" => Ok(DeviceKind::Ndarray),
            other => Err(XylemError::input(
                format!("$device {other:?}"),
                "expected `flex` (default) or `ndarray`",
            )),
        }
    }
}
