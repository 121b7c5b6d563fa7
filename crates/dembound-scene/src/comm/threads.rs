//! Ranks as threads of one process, messages over channels: the
//! decomposition tested without MPI (and the same code path as MPI: only
//! the transport differs).

use std::sync::mpsc::{channel, Receiver, Sender};

use super::Transport;

/// One rank's end of an all-to-all set of channels.
pub struct ThreadTransport {
    rank: usize,
    to: Vec<Sender<Vec<u8>>>,
    from: Vec<Receiver<Vec<u8>>>,
}

impl ThreadTransport {
    /// `ranks` connected transports, rank k at index k.
    pub fn group(ranks: usize) -> Vec<ThreadTransport> {
        let mut senders: Vec<Vec<Sender<Vec<u8>>>> = (0..ranks).map(|_| Vec::new()).collect();
        let mut receivers: Vec<Vec<Receiver<Vec<u8>>>> = (0..ranks).map(|_| Vec::new()).collect();
        // Channel src → dst: the sender kept by src, the receiver by dst
        // (at receivers[dst][src]).
        for to in senders.iter_mut() {
            for from in receivers.iter_mut() {
                let (s, r) = channel();
                to.push(s);
                from.push(r);
            }
        }
        senders
            .into_iter()
            .zip(receivers)
            .enumerate()
            .map(|(rank, (to, from))| ThreadTransport { rank, to, from })
            .collect()
    }

    fn send(&self, to: usize, bytes: Vec<u8>) {
        // A peer that has ended drops its receivers: its run is over and
        // nothing more is expected from this rank.
        let _ = self.to[to].send(bytes);
    }

    fn receive(&self, from: usize) -> Vec<u8> {
        match self.from[from].recv() {
            Ok(b) => b,
            // A peer panicked: end this rank too rather than hang.
            Err(_) => panic!("rank {from} ended before sending to rank {}", self.rank),
        }
    }

    fn everyone(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
        for r in 0..self.to.len() {
            self.send(r, bytes.to_vec());
        }
        (0..self.from.len()).map(|r| self.receive(r)).collect()
    }
}

fn f64s(b: &[u8]) -> Vec<f64> {
    b.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
        .collect()
}

impl Transport for ThreadTransport {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.to.len()
    }

    fn exchange(&self, sends: &[(usize, Vec<u8>)], from: &[usize]) -> Vec<Vec<u8>> {
        for (r, b) in sends {
            self.send(*r, b.clone());
        }
        from.iter().map(|&r| self.receive(r)).collect()
    }

    /// Sends, runs `work`, then receives (the channels buffer the sends).
    fn exchange_during(
        &self,
        sends: &[(usize, Vec<u8>)],
        from: &[usize],
        got: &mut [Vec<u8>],
        work: &mut dyn FnMut(&mut dyn FnMut()),
    ) {
        for (r, b) in sends {
            self.send(*r, b.clone());
        }
        work(&mut || {});
        for (&r, buf) in from.iter().zip(got.iter_mut()) {
            *buf = self.receive(r);
        }
    }

    fn who_sends(&self, to: &[bool]) -> Vec<bool> {
        for (r, &t) in to.iter().enumerate() {
            self.send(r, vec![u8::from(t)]);
        }
        (0..self.from.len())
            .map(|r| self.receive(r).first() == Some(&1))
            .collect()
    }

    fn max(&self, x: f64) -> f64 {
        self.everyone(&x.to_le_bytes())
            .iter()
            .flat_map(|b| f64s(b))
            .fold(
                f64::NEG_INFINITY,
                |a, b| if b > a || b.is_nan() { b } else { a },
            )
    }

    fn sum(&self, x: &[f64]) -> Vec<f64> {
        let bytes: Vec<u8> = x.iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut out = vec![0.0; x.len()];
        for b in self.everyone(&bytes) {
            for (o, v) in out.iter_mut().zip(f64s(&b)) {
                *o += v;
            }
        }
        out
    }

    fn all_gather(&self, x: f64) -> Vec<f64> {
        self.everyone(&x.to_le_bytes())
            .iter()
            .flat_map(|b| f64s(b))
            .collect()
    }

    fn gather(&self, bytes: Vec<u8>) -> Option<Vec<Vec<u8>>> {
        self.send(0, bytes);
        (self.rank == 0).then(|| (0..self.from.len()).map(|r| self.receive(r)).collect())
    }

    fn abort(&self, code: i32) -> ! {
        panic!("rank {} aborted the run (code {code})", self.rank)
    }
}
