//! The transport over MPI (rsmpi, Debian's Open MPI): feature `mpi`.

use mpi::collective::SystemOperation;
use mpi::environment::Universe;
use mpi::point_to_point::{Destination, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::CommunicatorCollectives;

use super::Transport;

/// MPI_COMM_WORLD; MPI ends (MPI_Finalize) when this is dropped.
pub struct MpiTransport {
    world: SimpleCommunicator,
    _universe: Universe,
}

impl MpiTransport {
    /// Initialises MPI (`None` if it was already initialised).
    pub fn init() -> Option<Self> {
        let universe = mpi::initialize()?;
        let world = universe.world();
        Some(Self {
            world,
            _universe: universe,
        })
    }

    /// Whether this process was started by an MPI launcher (`mpirun`,
    /// `srun`): Open MPI, MPICH/PMI and PMIx set these.
    pub fn launched() -> bool {
        ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
            .iter()
            .any(|v| std::env::var_os(v).is_some())
    }
}

impl Transport for MpiTransport {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn exchange(&self, sends: &[(usize, Vec<u8>)], from: &[usize]) -> Vec<Vec<u8>> {
        let world = &self.world;
        mpi::request::scope(|scope| {
            let requests: Vec<_> = sends
                .iter()
                .map(|(r, b)| {
                    world
                        .process_at_rank(*r as i32)
                        .immediate_send(scope, &b[..])
                })
                .collect();
            let out = from
                .iter()
                .map(|&r| world.process_at_rank(r as i32).receive_vec::<u8>().0)
                .collect();
            for r in requests {
                r.wait();
            }
            out
        })
    }

    /// Receives posted first (`MPI_Irecv` into the caller's buffers, of
    /// the messages' lengths), then the sends (`MPI_Isend`); `work` runs
    /// while they are in flight, its calls to its argument test them
    /// (`MPI_Test`: Open MPI moves messages only inside its calls); then
    /// every one is waited for.
    fn exchange_during(
        &self,
        sends: &[(usize, Vec<u8>)],
        from: &[usize],
        got: &mut [Vec<u8>],
        work: &mut dyn FnMut(&mut dyn FnMut()),
    ) {
        let world = &self.world;
        mpi::request::scope(|scope| {
            let mut requests: Vec<Option<_>> = Vec::with_capacity(from.len() + sends.len());
            for (&r, buf) in from.iter().zip(got.iter_mut()) {
                let p = world.process_at_rank(r as i32);
                requests.push(Some(p.immediate_receive_into(scope, &mut buf[..])));
            }
            for (r, b) in sends {
                let p = world.process_at_rank(*r as i32);
                requests.push(Some(p.immediate_send(scope, &b[..])));
            }
            work(&mut || {
                for slot in requests.iter_mut() {
                    if let Some(r) = slot.take() {
                        *slot = r.test().err();
                    }
                }
            });
            for r in requests.into_iter().flatten() {
                r.wait();
            }
        });
    }

    fn who_sends(&self, to: &[bool]) -> Vec<bool> {
        let send: Vec<u8> = to.iter().map(|&t| u8::from(t)).collect();
        let mut recv = vec![0u8; send.len()];
        self.world.all_to_all_into(&send[..], &mut recv[..]);
        recv.iter().map(|&b| b == 1).collect()
    }

    fn max(&self, x: f64) -> f64 {
        let mut y = 0.0f64;
        self.world
            .all_reduce_into(&x, &mut y, SystemOperation::max());
        y
    }

    fn sum(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        self.world
            .all_reduce_into(x, &mut y[..], SystemOperation::sum());
        y
    }

    fn all_gather(&self, x: f64) -> Vec<f64> {
        let mut y = vec![0.0; self.size()];
        self.world.all_gather_into(&x, &mut y[..]);
        y
    }

    fn gather(&self, bytes: Vec<u8>) -> Option<Vec<Vec<u8>>> {
        if self.rank() == 0 {
            let mut out = vec![bytes];
            for r in 1..self.size() {
                out.push(self.world.process_at_rank(r as i32).receive_vec::<u8>().0);
            }
            Some(out)
        } else {
            self.world.process_at_rank(0).send(&bytes[..]);
            None
        }
    }

    fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}
