//! Flicker: the mean absolute change of accessibility from one frame to the next, over the
//! non-sky pixels, averaged over every consecutive pair of frames of a run. On a still camera
//! (how `aograph bench` renders) a perfectly stable technique scores 0; per-frame noise or
//! an unconverged temporal filter scores higher.

/// Accumulates frames one at a time (no need to keep the run in memory).
#[derive(Clone, Debug, Default)]
pub struct FlickerMeter {
    previous: Option<Vec<f32>>,
    sum: f64,
    count: usize,
}

impl FlickerMeter {
    /// An empty meter: no frame pushed yet, so [`FlickerMeter::value`] is `None`.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the next frame; `mask` selects the pixels measured (non-sky).
    pub fn push(&mut self, frame: &[f32], mask: &[bool]) {
        if let Some(prev) = &self.previous {
            for ((a, b), m) in frame.iter().zip(prev).zip(mask) {
                if *m {
                    self.sum += (*a as f64 - *b as f64).abs();
                    self.count += 1;
                }
            }
        }
        self.previous = Some(frame.to_vec());
    }

    /// Mean absolute frame-to-frame change; `None` before two frames (or with an empty mask).
    pub fn value(&self) -> Option<f64> {
        (self.count > 0).then(|| self.sum / self.count as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_image_does_not_flicker() {
        let mut f = FlickerMeter::new();
        assert_eq!(f.value(), None);
        f.push(&[0.5; 4], &[true; 4]);
        assert_eq!(f.value(), None, "one frame has no change to measure");
        f.push(&[0.5; 4], &[true; 4]);
        assert_eq!(f.value(), Some(0.0));
    }

    #[test]
    fn alternating_frames_flicker_by_their_difference() {
        // 0.4, 0.6, 0.4 on two pixels (the third is sky and changes wildly): change 0.2 per pair.
        let mask = [true, true, false];
        let mut f = FlickerMeter::new();
        f.push(&[0.4, 0.4, 0.0], &mask);
        f.push(&[0.6, 0.6, 1.0], &mask);
        f.push(&[0.4, 0.4, 0.0], &mask);
        assert!((f.value().unwrap() - 0.2).abs() < 1e-6);
    }
}
