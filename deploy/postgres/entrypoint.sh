#!/bin/sh
# First start: a cluster owned by POSTGRES_USER with password POSTGRES_PASSWORD (scram), the
# database POSTGRES_DB, password logins from the network. Later starts reuse PGDATA as it is.
# PGPORT (default 5432) is the port. Runs as user postgres; postgres replaces this shell.
set -eu
: "${PGDATA:?}" "${POSTGRES_USER:?set POSTGRES_USER}" "${POSTGRES_PASSWORD:?set POSTGRES_PASSWORD}"
: "${POSTGRES_DB:=$POSTGRES_USER}" "${PGPORT:=5432}"
if [ ! -s "$PGDATA/PG_VERSION" ]; then
  pwfile=$(mktemp)
  printf '%s\n' "$POSTGRES_PASSWORD" > "$pwfile"
  initdb -D "$PGDATA" -U "$POSTGRES_USER" --pwfile="$pwfile" --auth-local=trust --auth-host=scram-sha-256 >/dev/null
  rm -f "$pwfile"
  echo "host all all all scram-sha-256" >> "$PGDATA/pg_hba.conf"
  sock=$(mktemp -d)
  pg_ctl -D "$PGDATA" -o "-c listen_addresses= -k $sock -p $PGPORT" -w start >/dev/null
  if [ "$POSTGRES_DB" != postgres ]; then createdb -h "$sock" -p "$PGPORT" -U "$POSTGRES_USER" "$POSTGRES_DB"; fi
  pg_ctl -D "$PGDATA" -m fast -w stop >/dev/null
  rmdir "$sock"
fi
exec postgres -D "$PGDATA" -c listen_addresses='*' -p "$PGPORT" -k /tmp
