//! Atomic writes: each write of the store is one transaction, or, inside
//! [`Store::atomically`], a savepoint of the caller's one transaction, so that a whole import
//! lands or leaves the file as it was.

use std::ops::Deref;

use rusqlite::{Connection, Savepoint, Transaction, TransactionBehavior};

use crate::database::Store;
use crate::error::{Result, StoreError};

/// One write in progress: its own transaction, or a savepoint inside a larger one. Dropped
/// without [`Write::commit`], it is rolled back.
pub(crate) enum Write<'a> {
    Own(Transaction<'a>),
    Nested(Savepoint<'a>),
}

impl Deref for Write<'_> {
    type Target = Connection;

    fn deref(&self) -> &Connection {
        match self {
            Write::Own(tx) => tx,
            Write::Nested(sp) => sp,
        }
    }
}

impl Write<'_> {
    pub(crate) fn commit(self) -> Result<()> {
        match self {
            Write::Own(tx) => tx.commit()?,
            Write::Nested(sp) => sp.commit()?,
        }
        Ok(())
    }
}

impl Store {
    /// Begin one write: an IMMEDIATE transaction (the write lock taken up front), or a
    /// savepoint when [`Store::atomically`] already holds one.
    pub(crate) fn write(&mut self) -> Result<Write<'_>> {
        Ok(if self.conn.is_autocommit() {
            Write::Own(
                self.conn
                    .transaction_with_behavior(TransactionBehavior::Immediate)?,
            )
        } else {
            Write::Nested(self.conn.savepoint()?)
        })
    }

    /// Run `f` as one transaction (or as a savepoint of the one already open): every write
    /// it makes lands, or, on an error, none does.
    pub fn atomically<T, E: From<StoreError>>(
        &mut self,
        f: impl FnOnce(&mut Store) -> std::result::Result<T, E>,
    ) -> std::result::Result<T, E> {
        let outer = self.conn.is_autocommit();
        let (begin, end, undo) = if outer {
            ("BEGIN IMMEDIATE", "COMMIT", "ROLLBACK")
        } else {
            (
                "SAVEPOINT atomically",
                "RELEASE atomically",
                "ROLLBACK TO atomically; RELEASE atomically",
            )
        };
        self.conn.execute_batch(begin).map_err(StoreError::from)?;
        let done = f(self).and_then(|v| {
            self.conn.execute_batch(end).map_err(StoreError::from)?;
            Ok(v)
        });
        if done.is_err() && !(outer && self.conn.is_autocommit()) {
            // (Should this fail too, closing the connection rolls back.)
            let _ = self.conn.execute_batch(undo);
        }
        done
    }
}
